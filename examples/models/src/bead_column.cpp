#include "mimpact/models/bead_column.hpp"

#include "mimpact/granular/hertz.hpp"
#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/linear_relation.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::models {

double BeadColumn::mass() const { return granular::bead_mass(radius, {density, young, poisson}); }

std::shared_ptr<kernel::NonSmoothDynamicalSystem> BeadColumn::build() const {
  const granular::Material steel{density, young, poisson};
  auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  std::vector<std::shared_ptr<kernel::DynamicalSystem>> bodies;
  for (int i = 0; i <= beads; ++i) {
    kernel::LagrangianLinearTIDS::Matrices matrices;
    matrices.mass = Eigen::MatrixXd::Constant(1, 1, mass());
    matrices.external_force = Eigen::VectorXd::Constant(1, -mass() * gravity);
    const double height = radius * (2 * i + 1) + (i == beads ? drop_height : 0.0);
    bodies.push_back(std::make_shared<kernel::LagrangianLinearTIDS>(
        Eigen::VectorXd::Constant(1, height), Eigen::VectorXd::Zero(1), matrices,
        i == beads ? "striker" : "bead " + std::to_string(i)));
    system->add(bodies.back());
  }
  numerics::ContactLaw floor_law, bead_law;
  floor_law.stiffness = granular::hertz_stiffness_wall(radius, steel, steel);
  bead_law.stiffness = granular::hertz_stiffness(radius, steel, radius, steel);
  floor_law.restitution = bead_law.restitution = restitution;
  system->add(std::make_shared<kernel::Interaction>(
      bodies[0], std::make_shared<kernel::LinearRelation>(Eigen::RowVectorXd::Ones(1), -radius),
      std::make_shared<plugins::LzbLaw>(floor_law), "floor"));
  for (int i = 1; i <= beads; ++i)
    system->add(std::make_shared<kernel::Interaction>(
        bodies[i - 1], bodies[i],
        std::make_shared<kernel::LinearRelation>(Eigen::RowVector2d(-1.0, 1.0), -2.0 * radius),
        std::make_shared<plugins::LzbLaw>(bead_law), "contact " + std::to_string(i)));
  return system;
}

double BeadColumn::energy(const kernel::NonSmoothDynamicalSystem& system) const {
  double total = 0.0;
  for (kernel::Index k = 0; k < system.system_count(); ++k) {
    const double z = system.system(k).position()(0), v = system.system(k).velocity()(0);
    total += mass() * (0.5 * v * v + gravity * z);
  }
  return total;
}

}  // namespace mimpact::models
