// `mimpact chain` through the kernel: the same impact as numerics alone, a striker that
// flies to the chain first (example b), and nothing built that the scene does not need.
#include <gtest/gtest.h>

#include "../support/chain_runs.hpp"
#include "mimpact/chains/chain_impact.hpp"
#include "mimpact/kernel/simulation.hpp"
#include "mimpact/plugins/acceleration_lcp_problem.hpp"
#include "mimpact/plugins/event_driven_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"

namespace mimpact::testing {
namespace {

TEST(ChainThroughKernel, SameImpactAsNumericsAloneToRoundOff) {
  for (const char* scene : {"c1.json", "c2.json", "c3.json"}) {
    const chains::ChainModel model = scene_model(scene);
    const granular::ImpactOutcome kernel = run_chain(model, 1e-5);
    numerics::LzbOptions options;
    options.delta_p = 1e-5;
    const granular::ImpactOutcome direct = chains::simulate_chain_impact_numerics(model, options);
    EXPECT_EQ(kernel.result.steps, direct.result.steps) << scene;
    EXPECT_LE(relative_difference(kernel.velocity_after, direct.velocity_after), 1e-12) << scene;
    EXPECT_LE((kernel.result.max_force - direct.result.max_force).cwiseAbs().maxCoeff(),
              1e-12 * direct.result.max_force.maxCoeff())
        << scene;
  }
}

chains::ChainModel ten_bead_chain(double gap, double speed) {
  const std::string text =
      R"({"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
          "chain": {"segments": [{"count": 10, "radius": 0.01}]},
          "strikers": [{"radius": 0.01, "velocity": )" +
      std::to_string(speed) + R"(, "gap": )" + std::to_string(gap) +
      R"(}], "contact": {"restitution": 0.9}})";
  return chains::build_chain_model(chains::parse_chain_scene(text, "ten beads"));
}

// Example b: the striker released at distance d with speed V meets the chain at d / V and
// the impact is the zero-gap one.
TEST(ChainThroughKernel, StrikerFliesToTheChainThenTheSameImpact) {
  const double speed = 0.8;
  const chains::ChainModel touching = ten_bead_chain(0.0, speed);
  const granular::ImpactOutcome reference = run_chain(touching, 1e-6);
  for (double gap : {1e-4, 0.0123, 0.5}) {
    const chains::ChainModel flying = ten_bead_chain(gap, speed);
    const granular::ImpactOutcome impact = run_chain(flying, 1e-6);
    EXPECT_NEAR(impact.impact_time, gap / speed, 1e-10 + 1e-15 * gap / speed) << gap;
    EXPECT_LE(relative_difference(impact.velocity_after, reference.velocity_after), 1e-12) << gap;
  }
}

// A chain with neither gravity nor persistent contacts integrates no differential equation
// and builds no LCP, even when its beads lock together (C3, e = 0.6).
TEST(ChainThroughKernel, NoOdeAndNoLcpWithoutForces) {
  for (const char* scene : {"c1.json", "c3.json"}) {
    const chains::ChainModel model = scene_model(scene);
    plugins::LzbImpactOptions options;
    options.delta_p = 1e-5;
    auto integrator = std::make_unique<plugins::EventDrivenIntegrator>();
    auto lcp = std::make_unique<plugins::AccelerationLcpProblem>();
    const plugins::EventDrivenIntegrator& ed = *integrator;
    const plugins::AccelerationLcpProblem& forces = *lcp;
    kernel::Simulation simulation(chains::build_chain_system(model), std::move(integrator),
                                  {.impacts = std::make_unique<plugins::LzbImpactProblem>(options),
                                   .contact_forces = std::move(lcp)});
    const kernel::RunSummary summary = simulation.run(0.0, 0.01);  // past the impact
    // the impact, and for C3 the follow-ups of beads locked within the impact's resolution
    EXPECT_GE(summary.impacts, 1) << scene;
    EXPECT_EQ(summary.smooth_steps, 0) << scene;
    EXPECT_FALSE(ed.integrates_ode()) << scene;
    EXPECT_EQ(forces.lcp_count(), 0) << scene;
  }
}

}  // namespace
}  // namespace mimpact::testing
