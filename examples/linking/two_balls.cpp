// Two steel balls collide head on; the LZB law must give them back e times their approach
// speed. Exits non-zero when it does not, so the build of this file is also a check of the
// installed package.
#include <cmath>
#include <cstdio>
#include <mimpact/numerics/lzb_impulse_integrator.hpp>

int main() {
  using namespace mimpact::numerics;
  const double m1 = 0.0326, m2 = 0.0652;  // kg
  const double restitution = 0.8;
  const ContactLaw law{.stiffness = 1.05e10, .exponent = 1.5, .restitution = restitution};
  const Eigen::MatrixXd H = Eigen::MatrixXd::Constant(1, 1, 1.0 / m1 + 1.0 / m2);
  const Eigen::VectorXd u_minus = Eigen::VectorXd::Constant(1, -1.0);  // approaching at 1 m/s
  LzbImpulseIntegrator integrator({.delta_p = 1e-6});
  const LzbResult result = integrator.integrate(H, u_minus, std::span(&law, 1));
  std::printf("separation speed %.6f m/s (e = %.2f), %lld impulse steps, contact %.3g s\n",
              result.velocity(0), restitution, (long long)result.steps, result.duration);
  return std::abs(result.velocity(0) - restitution) < 1e-3 ? 0 : 1;
}
