#include "mimpact/models/rocking_block.hpp"

#include <cmath>

#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/scleronomous_relation.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::models {

std::shared_ptr<kernel::NonSmoothDynamicalSystem> RockingBlock::build() const {
  kernel::LagrangianLinearTIDS::Matrices matrices;
  matrices.mass = Eigen::Vector3d(mass, mass, inertia()).asDiagonal();
  matrices.external_force = Eigen::Vector3d(0.0, -mass * gravity, 0.0);
  // the lower corner (the +w/2 one for a positive tilt) drop_height above the floor
  const double y = drop_height + (height / 2) * std::cos(tilt) + (width / 2) * std::sin(tilt);
  auto block = std::make_shared<kernel::LagrangianLinearTIDS>(
      Eigen::Vector3d(0.0, y, tilt), Eigen::Vector3d::Zero(), matrices, "block");
  auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  system->add(block);
  numerics::ContactLaw law;
  law.stiffness = stiffness;
  law.restitution = restitution;
  law.friction = friction;
  const double a = width / 2, b = height / 2;
  for (double side : {-1.0, 1.0}) {
    auto relation = std::make_shared<kernel::ScleronomousRelation>(
        [a, b, side](const Eigen::VectorXd& q) {
          return q(1) + side * a * std::sin(q(2)) - b * std::cos(q(2));
        },
        [a, b, side](const Eigen::VectorXd& q, Eigen::RowVectorXd& row) {
          row << 0.0, 1.0, side * a * std::cos(q(2)) + b * std::sin(q(2));
        },
        [a, b, side](const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
          return v(2) * v(2) * (-side * a * std::sin(q(2)) + b * std::cos(q(2)));
        });
    if (friction > 0.0)
      relation->set_tangents(
          1,
          [a, b, side](const Eigen::VectorXd& q, Eigen::MatrixXd& rows) {
            rows << 1.0, 0.0, b * std::cos(q(2)) - side * a * std::sin(q(2));
          },
          [a, b, side](const Eigen::VectorXd& q, const Eigen::VectorXd& v, Eigen::VectorXd& rates) {
            rates(0) = -v(2) * v(2) * (b * std::sin(q(2)) + side * a * std::cos(q(2)));
          });
    system->add(std::make_shared<kernel::Interaction>(block, relation,
                                                      std::make_shared<plugins::LzbLaw>(law),
                                                      side < 0 ? "corner -w/2" : "corner +w/2"));
  }
  return system;
}

double RockingBlock::energy(const kernel::NonSmoothDynamicalSystem& system) const {
  const Eigen::VectorXd& q = system.system(0).position();
  const Eigen::VectorXd& v = system.system(0).velocity();
  return 0.5 * mass * (v(0) * v(0) + v(1) * v(1)) + 0.5 * inertia() * v(2) * v(2) +
         mass * gravity * q(1);
}

}  // namespace mimpact::models
