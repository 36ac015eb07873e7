#include "mimpact/models/newtons_cradle.hpp"

#include <cmath>

#include "mimpact/granular/hertz.hpp"
#include "mimpact/kernel/lagrangian_ds.hpp"
#include "mimpact/kernel/scleronomous_relation.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::models {

namespace {

// Geometry of the contact between pendulums i and i+1 with pivots `spacing` apart, on the
// stacked angles (theta_i, theta_{i+1}).
struct BallPair {
  double length, spacing, contact_distance;

  Eigen::Vector2d separation(const Eigen::VectorXd& theta) const {  // c_{i+1} - c_i
    return {spacing + length * (std::sin(theta(1)) - std::sin(theta(0))),
            -length * (std::cos(theta(1)) - std::cos(theta(0)))};
  }
  double gap(const Eigen::VectorXd& theta) const {
    return separation(theta).norm() - contact_distance;
  }
  void jacobian(const Eigen::VectorXd& theta, Eigen::RowVectorXd& row) const {
    const Eigen::Vector2d d = separation(theta);
    const double n = d.norm();
    const Eigen::Vector2d dc0(length * std::cos(theta(0)), length * std::sin(theta(0)));
    const Eigen::Vector2d dc1(length * std::cos(theta(1)), length * std::sin(theta(1)));
    row(0) = -d.dot(dc0) / n;
    row(1) = d.dot(dc1) / n;
  }
  // v^T (d^2 g / d theta^2) v = (|d'|^2 + d . d''_rate) / |d| - (d . d')^2 / |d|^3
  double rate(const Eigen::VectorXd& theta, const Eigen::VectorXd& omega) const {
    const Eigen::Vector2d d = separation(theta);
    const double n = d.norm();
    const Eigen::Vector2d d_dot =
        length * omega(1) * Eigen::Vector2d(std::cos(theta(1)), std::sin(theta(1))) -
        length * omega(0) * Eigen::Vector2d(std::cos(theta(0)), std::sin(theta(0)));
    const Eigen::Vector2d d_ddot =
        length * omega(1) * omega(1) * Eigen::Vector2d(-std::sin(theta(1)), std::cos(theta(1))) -
        length * omega(0) * omega(0) * Eigen::Vector2d(-std::sin(theta(0)), std::cos(theta(0)));
    const double along = d.dot(d_dot);
    return (d_dot.squaredNorm() + d.dot(d_ddot)) / n - along * along / (n * n * n);
  }
};

}  // namespace

double NewtonsCradle::mass() const {
  return granular::bead_mass(radius, {density, young, poisson});
}

double NewtonsCradle::hertz_stiffness() const {
  const granular::Material steel{density, young, poisson};
  return granular::hertz_stiffness(radius, steel, radius, steel);
}

std::shared_ptr<kernel::NonSmoothDynamicalSystem> NewtonsCradle::build() const {
  auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  const double m = mass(), L = length, g = gravity;
  std::vector<std::shared_ptr<kernel::LagrangianDS>> bodies;
  for (int i = 0; i < pendulums; ++i) {
    auto pendulum = std::make_shared<kernel::LagrangianDS>(
        Eigen::VectorXd::Constant(1, i == 0 ? release_angle : 0.0), Eigen::VectorXd::Zero(1),
        Eigen::MatrixXd::Constant(1, 1, m * L * L), "pendulum " + std::to_string(i));
    pendulum->set_internal_force(
        [m, g, L](double, const Eigen::VectorXd& theta, const Eigen::VectorXd&,
                  Eigen::VectorXd& f) { f(0) = m * g * L * std::sin(theta(0)); });
    system->add(pendulum);
    bodies.push_back(pendulum);
  }
  numerics::ContactLaw law;
  law.stiffness = hertz_stiffness();
  law.restitution = restitution;
  for (int i = 0; i + 1 < pendulums; ++i) {
    const BallPair pair{L, 2.0 * radius, 2.0 * radius};
    auto relation = std::make_shared<kernel::ScleronomousRelation>(
        [pair](const Eigen::VectorXd& q) { return pair.gap(q); },
        [pair](const Eigen::VectorXd& q, Eigen::RowVectorXd& row) { pair.jacobian(q, row); },
        [pair](const Eigen::VectorXd& q, const Eigen::VectorXd& v) { return pair.rate(q, v); });
    system->add(std::make_shared<kernel::Interaction>(
        bodies[i], bodies[i + 1], relation, std::make_shared<plugins::LzbLaw>(law),
        "balls " + std::to_string(i) + "-" + std::to_string(i + 1)));
  }
  return system;
}

double NewtonsCradle::energy(const kernel::NonSmoothDynamicalSystem& system) const {
  double total = 0.0;
  const double m = mass(), L = length;
  for (kernel::Index k = 0; k < system.system_count(); ++k) {
    const double theta = system.system(k).position()(0), omega = system.system(k).velocity()(0);
    total += 0.5 * m * L * L * omega * omega + m * gravity * L * (1.0 - std::cos(theta));
  }
  return total;
}

}  // namespace mimpact::models
