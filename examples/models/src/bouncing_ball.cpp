#include "mimpact/models/bouncing_ball.hpp"

#include "mimpact/granular/hertz.hpp"
#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/linear_relation.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::models {

double BouncingBall::mass() const { return granular::bead_mass(radius, {density, young, poisson}); }

std::shared_ptr<kernel::NonSmoothDynamicalSystem> BouncingBall::build() const {
  const granular::Material steel{density, young, poisson};
  kernel::LagrangianLinearTIDS::Matrices matrices;
  matrices.mass = Eigen::MatrixXd::Constant(1, 1, mass());
  matrices.external_force = Eigen::VectorXd::Constant(1, -mass() * gravity);
  auto ball = std::make_shared<kernel::LagrangianLinearTIDS>(
      Eigen::VectorXd::Constant(1, drop_height), Eigen::VectorXd::Zero(1), matrices, "ball");
  numerics::ContactLaw law;
  law.stiffness = granular::hertz_stiffness_wall(radius, steel, steel);
  law.restitution = restitution;
  auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  system->add(ball);
  system->add(std::make_shared<kernel::Interaction>(
      ball, std::make_shared<kernel::LinearRelation>(Eigen::RowVectorXd::Ones(1), -radius),
      std::make_shared<plugins::LzbLaw>(law), "floor"));
  return system;
}

}  // namespace mimpact::models
