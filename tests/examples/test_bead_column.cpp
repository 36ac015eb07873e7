// Example d: a column of beads resting on the floor, struck from above. Before the strike
// every contact carries the weight of the beads above it; after the wave it settles again,
// now under one more bead.
#include <gtest/gtest.h>

#include "mimpact/models/bead_column.hpp"
#include "mimpact/models/simulation_setup.hpp"

namespace mimpact::models {
namespace {

struct Forces : kernel::SimulationObserver {
  kernel::EventStatus on_step(const kernel::Simulation&, const kernel::StepReport& step) override {
    if (step.contact_forces) {
      if (!first) first = *step.contact_forces;
      last = *step.contact_forces;
    }
    return kernel::EventStatus::proceed();
  }
  std::optional<kernel::ContactForces> first, last;
};

TEST(BeadColumn, WeightsBeforeTheStrikeAndSettledAfter) {
  const BeadColumn column;
  SimulationSetup setup;
  setup.impacts.relative_delta_p = 1e-3;
  auto system = column.build();
  const double start_energy = column.energy(*system);
  kernel::Simulation simulation = make_simulation(system, setup);
  Forces forces;
  simulation.add_observer(forces);
  const kernel::RunSummary summary = simulation.run(0.0, 1.0);

  const double weight = column.mass() * column.gravity;
  ASSERT_TRUE(forces.first);
  EXPECT_EQ(forces.first->time, 0.0);
  ASSERT_EQ(forces.first->force.size(), column.beads);  // the striker is still falling
  for (int j = 0; j < column.beads; ++j)
    EXPECT_NEAR(forces.first->force(j), (column.beads - j) * weight, 1e-12 * column.beads * weight)
        << "contact " << j;

  EXPECT_GE(summary.impacts, 2);
  ASSERT_TRUE(forces.last);
  ASSERT_EQ(forces.last->force.size(), column.beads + 1);
  for (int j = 0; j <= column.beads; ++j)
    EXPECT_NEAR(forces.last->force(j), (column.beads + 1 - j) * weight,
                1e-9 * (column.beads + 1) * weight)
        << "contact " << j;
  EXPECT_EQ(system->index_sets().persistent.size(), std::size_t(column.beads + 1));
  for (kernel::Index k = 0; k < system->system_count(); ++k) {
    EXPECT_NEAR(system->system(k).position()(0), column.radius * (2 * k + 1), 1e-12) << k;
    EXPECT_NEAR(system->system(k).velocity()(0), 0.0, 1e-12) << k;
  }
  EXPECT_LT(column.energy(*system), start_energy);
}

}  // namespace
}  // namespace mimpact::models
