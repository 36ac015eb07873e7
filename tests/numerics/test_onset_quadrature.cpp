#include "mimpact/numerics/onset_quadrature.hpp"

#include <gtest/gtest.h>

#include <array>
#include <boost/math/quadrature/tanh_sinh.hpp>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <span>
#include <vector>

#include "mimpact/numerics/runge_kutta_nystrom.hpp"

// The quadrature of a Hertz force across its onset within a step (onset_quadrature.hpp):
// against the closed form and an independent adaptive quadrature, and the order it gives the
// Nystrom step across a collision's first touch.
namespace mimpact::numerics {
namespace {

constexpr double kReach = 0.01;        // m: two beads of 5 mm
constexpr double kStiffness = 7.43e9;  // N / m^(3/2): steel, (4/3) E* sqrt(R*)

// The force (N) on the second bead at separation r (m), as the Hertz law gives it.
double hertz(const Eigen::Vector3d& r) {
  const double delta = kReach - r.norm();
  return delta > 0.0 ? kStiffness * delta * std::sqrt(delta) : 0.0;
}

// What the weights b at the nodes c take of the force along r(s).
template <class Separation>
double weighted(Separation&& r) {
  double sum = 0.0;
  for (std::size_t i = 0; i < 4; ++i) sum += rkn43::velocity_weights[i] * hertz(r(rkn43::nodes[i]));
  return sum;
}

TEST(OnsetQuadrature, MatchesTheClosedFormOfALinearApproach) {
  // separation falling linearly by w (m over the step): overlap w (s - s*) from s* on, whose
  // force integrates to K w^(3/2) (1 - s*)^(5/2) / (5/2)
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, 2.0, 2.0) / 3.0;
  for (double onset : {0.0, 0.13, 0.5, 0.87}) {
    const double w = 2e-6;
    const Eigen::Vector3d r0 = (kReach + onset * w) * axis, u = -w * axis, r1 = r0 + u;
    const OnsetQuadrature missed =
        hertz_onset_quadrature({.r0 = r0, .u0 = u, .r1 = r1, .u1 = u}, kReach, kStiffness,
                               rkn43::nodes, rkn43::velocity_weights);
    const double exact = kStiffness * std::pow(w, 1.5) * std::pow(1.0 - onset, 2.5) / 2.5;
    const double by_weights = weighted([&](double s) { return Eigen::Vector3d(r0 + s * u); });
    // the overlaps are differences of lengths 5 000 times larger: rounded to ~1e-12 of theirs
    EXPECT_NEAR(missed.magnitude + by_weights, exact, 1e-10 * exact) << "onset at " << onset;
    // along the line of centres, pushing the second bead away from the first
    EXPECT_NEAR((missed.impulse - missed.magnitude * axis).norm(), 0.0,
                1e-12 * std::abs(missed.magnitude));
  }
}

TEST(OnsetQuadrature, MatchesAnAdaptiveQuadratureOfAGrazingTouch) {
  // the beads graze, touching and parting within the step (overlapping by at most 2e-7 m over
  // its middle 64 %), the second turning and slowing: against tanh-sinh on the same cubic, which
  // knows nothing of the spans
  const Eigen::Vector3d r0(kReach - 2e-7, -1e-4, 0.0), r1(kReach - 2.2e-7, 1e-4, 1e-6);
  const Eigen::Vector3d u0(1e-7, 2.2e-4, 0.0), u1(-1e-7, 1.8e-4, 2e-6);
  auto separation = [&](double s) -> Eigen::Vector3d {
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * r0 + (s3 - 2 * s2 + s) * u0 + (3 * s2 - 2 * s3) * r1 +
           (s3 - s2) * u1;
  };
  const OnsetQuadrature missed =
      hertz_onset_quadrature({.r0 = r0, .u0 = u0, .r1 = r1, .u1 = u1}, kReach, kStiffness,
                             rkn43::nodes, rkn43::velocity_weights);
  ASSERT_GT(hertz(separation(0.5)), 0.0);
  ASSERT_EQ(hertz(separation(0.0)) + hertz(separation(1.0)), 0.0);
  boost::math::quadrature::tanh_sinh<double> adaptive;
  double total = 0.0;
  for (int part = 0; part < 64; ++part)  // the spans' ends lie inside some of these parts
    total += adaptive.integrate([&](double s) { return hertz(separation(s)); }, part / 64.0,
                                (part + 1) / 64.0, 1e-15);
  // (tanh-sinh within 5e-12 of a 40-digit mpmath quadrature between the roots; the module's
  // eight Gauss points a half-span 1.8e-10 off, its overlap's square root analytic only out to
  // 1.4 times the half-span: far below what an amendment of 1e-2 of a step's impulse needs)
  EXPECT_NEAR(missed.magnitude + weighted(separation), total, 1e-9 * total);
}

// Two beads of mass m closing head on at V, one Nystrom step of h across their first touch
// at half the step, in the moving geometry's state: y = (x_a, x_b, w_a, w_b, q), T = 1.
constexpr double kMass = 4.07e-3, kSpeed = 1.0;

struct Collision {
  void operator()(const std::vector<double>& y, std::vector<double>& dydt, double) const {
    const double f = hertz(Eigen::Vector3d(y[1] - y[0], 0.0, 0.0));
    dydt[2] = -f / kMass;
    dydt[3] = f / kMass;
    dydt[4] = f;
  }
};
struct AmendedCollision : Collision {
  void amend(const std::vector<double>& y0, const std::vector<double>&, std::vector<double>& y1,
             const std::vector<double>&, double h, std::span<const std::size_t> switching) const {
    if (switching.empty()) return;
    const OnsetQuadrature missed =
        hertz_onset_quadrature({.r0 = Eigen::Vector3d(y0[1] - y0[0], 0, 0),
                                .u0 = Eigen::Vector3d(h * (y0[3] - y0[2]), 0, 0),
                                .r1 = Eigen::Vector3d(y1[1] - y1[0], 0, 0),
                                .u1 = Eigen::Vector3d(h * (y1[3] - y1[2]), 0, 0)},
                               kReach, kStiffness, rkn43::nodes, rkn43::velocity_weights);
    y1[2] -= h * missed.impulse.x() / kMass;
    y1[3] += h * missed.impulse.x() / kMass;
    y1[4] += h * missed.magnitude;
  }
};

// The second bead's velocity (m/s) after one step of h, its touch at h / 2.
template <class Motion>
double velocity_after_step(double h) {
  OdeOptions options;
  options.absolute_tolerance = 1e300;  // one step of h, never rejected
  options.relative_tolerance = 0.0;
  RungeKuttaNystrom rkn(options);
  const double gap = 0.5 * h * kSpeed;
  rkn.restart({0.0, kReach + gap, 0.5 * kSpeed, -0.5 * kSpeed, 0.0}, 0.0, h, 2, 1.0);
  Motion motion;
  rkn.step(motion);
  return rkn.state()[3];
}

// The same, exactly: free flight to the touch, then the overlap delta'' = -(2 / m) K delta^1.5
// from (0, V) integrated by Dormand-Prince (Boost.Odeint) to round-off over the half step.
double exact_velocity_after(double h) {
  using Pair = std::array<double, 2>;
  Pair state{0.0, kSpeed};
  auto rhs = [](const Pair& s, Pair& dsdt, double) {
    dsdt[0] = s[1];
    dsdt[1] = -2.0 / kMass * kStiffness * std::max(s[0], 0.0) * std::sqrt(std::max(s[0], 0.0));
  };
  namespace odeint = boost::numeric::odeint;
  odeint::integrate_adaptive(
      odeint::make_controlled(1e-16, 1e-16, odeint::runge_kutta_dopri5<Pair>()), rhs, state, 0.0,
      0.5 * h, 1e-3 * h);
  return -0.5 * state[1];  // the second bead's half of the closing speed
}

TEST(OnsetQuadrature, RaisesTheNystromStepsOrderAcrossATouch) {
  // the velocity's error after one step across the touch falls as h^2.5 with the weights
  // alone, and as h^5 (a smooth force's) with the onset's quadrature amended: 45 times smaller
  // at h = 4 us (an eighth of the contact's duration), 1 460 times at 0.5 us
  std::vector<double> plain, amended;
  for (double h : {4e-6, 2e-6, 1e-6, 5e-7}) {
    const double exact = exact_velocity_after(h);
    plain.push_back(std::abs(velocity_after_step<Collision>(h) - exact));
    amended.push_back(std::abs(velocity_after_step<AmendedCollision>(h) - exact));
  }
  for (std::size_t i = 0; i + 1 < plain.size(); ++i) {
    const double plain_order = std::log2(plain[i] / plain[i + 1]);
    const double amended_order = std::log2(amended[i] / amended[i + 1]);
    EXPECT_NEAR(plain_order, 2.5, 0.15) << "h index " << i;
    EXPECT_NEAR(amended_order, 5.0, 0.15) << "h index " << i;
    EXPECT_LT(amended[i], plain[i] / 30.0) << "h index " << i;
  }
}

}  // namespace
}  // namespace mimpact::numerics
