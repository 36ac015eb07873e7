// Example e: a rigid block rocking on two corners of a frictionless floor, a contact
// Jacobian that turns with the block. Impacts at one corner give u+ = -e u- there, the
// horizontal velocity never changes, energy falls at impacts and is kept in flight, and
// the block comes to rest on both corners, each carrying half its weight.
#include <gtest/gtest.h>

#include <cmath>

#include "mimpact/models/rocking_block.hpp"
#include "mimpact/models/simulation_setup.hpp"

namespace mimpact::models {
namespace {

struct Rocking : kernel::SimulationObserver {
  const RockingBlock* block = nullptr;
  void on_impact(const kernel::Simulation& simulation,
                 const kernel::ImpactReport& report) override {
    const double energy = block->energy(simulation.system());
    impacts.push_back(report);
    energies_after.push_back(energy);
    horizontal.push_back(simulation.system().system(0).velocity()(0));
  }
  kernel::EventStatus on_step(const kernel::Simulation& simulation,
                              const kernel::StepReport& step) override {
    energies_at_steps.push_back({step.time, block->energy(simulation.system()), step.event});
    if (step.contact_forces) forces = *step.contact_forces;
    return kernel::EventStatus::proceed();
  }
  struct Sample {
    double time, energy;
    bool event;
  };
  std::vector<kernel::ImpactReport> impacts;
  std::vector<double> energies_after, horizontal;
  std::vector<Sample> energies_at_steps;
  std::optional<kernel::ContactForces> forces;
};

TEST(RockingBlock, RocksLosesEnergyAndRestsOnBothCorners) {
  const RockingBlock block;
  SimulationSetup setup;
  setup.impacts.relative_delta_p = 1e-3;
  auto system = block.build();
  const double start_energy = block.energy(*system);
  kernel::Simulation simulation = make_simulation(system, setup);
  Rocking rocking;
  rocking.block = &block;
  simulation.add_observer(rocking);
  simulation.run(0.0, 2.0);

  ASSERT_GE(rocking.impacts.size(), 5u);
  double previous = start_energy;
  for (std::size_t k = 0; k < rocking.impacts.size(); ++k) {
    const kernel::ImpactReport& impact = rocking.impacts[k];
    if (impact.interactions.size() == 1) {
      EXPECT_NEAR(impact.result.velocity(0), -block.restitution * impact.velocity_before(0),
                  1e-9 * std::abs(impact.velocity_before(0)))
          << "impact " << k;
    }
    EXPECT_EQ(rocking.horizontal[k], 0.0);  // frictionless: no horizontal impulse
    EXPECT_LT(rocking.energies_after[k], previous) << "impact " << k;
    previous = rocking.energies_after[k];
  }
  // between impacts the energy is kept to the ODE tolerance
  for (std::size_t k = 1; k < rocking.energies_at_steps.size(); ++k) {
    const auto& a = rocking.energies_at_steps[k - 1];
    const auto& b = rocking.energies_at_steps[k];
    if (!b.event) {
      EXPECT_NEAR(b.energy, a.energy, 1e-7 * start_energy) << "step " << k;
    }
  }

  const Eigen::VectorXd& q = system->system(0).position();
  EXPECT_NEAR(q(2), 0.0, 1e-6);
  EXPECT_NEAR(q(1), block.height / 2, 1e-8);
  EXPECT_EQ(system->index_sets().persistent.size(), 2u);
  ASSERT_TRUE(rocking.forces);
  ASSERT_EQ(rocking.forces->force.size(), 2);
  const double half_weight = block.mass * block.gravity / 2;
  EXPECT_NEAR(rocking.forces->force(0), half_weight, 1e-6 * half_weight);
  EXPECT_NEAR(rocking.forces->force(1), half_weight, 1e-6 * half_weight);
}

}  // namespace
}  // namespace mimpact::models
