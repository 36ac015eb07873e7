// The adaptive LZB integrator chosen in a scene ("impact": {"integrator": "adaptive",
// "tolerance": eps}) and run through the kernel like the impulse steps.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "../support/chain_runs.hpp"
#include "../support/hertz_chain_reference.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/kernel/registry.hpp"
#include "mimpact/plugins/register_plugins.hpp"

namespace mimpact::testing {
namespace {

chains::ChainImpact run_adaptive(const chains::ChainModel& model, double tolerance) {
  plugins::LzbImpactOptions options;
  options.integrator = plugins::LzbIntegrator::adaptive;
  options.adaptive.tolerance = tolerance;
  return chains::simulate_chain_impact(model, options);
}

// Issue 10 (a): for e = 1 the continuous LZB impact is the Hertz chain; at tolerance 1e-10
// the adaptive integrator is within 1e-8 of the tests' own integration in time.
TEST(AdaptiveChains, ElasticChainsAreTheExactHertzChain) {
  for (const char* scene : {"c1.json", "c2.json"}) {
    const chains::ChainModel model = scene_model(scene);
    const chains::ChainImpact impact = run_adaptive(model, 1e-10);
    ASSERT_EQ(impact.lzb.status, numerics::LzbStatus::terminated);
    const Eigen::VectorXd exact =
        integrate_hertz_chain(model.mass, model.velocity, stiffnesses(model)).velocity;
    const double error = relative_difference(impact.velocity_after, exact);
    std::printf("%s, adaptive at 1e-10: ||v+ - v+_Hertz|| / ||v+_Hertz|| = %.2g in %lld steps\n",
                scene, error, (long long)impact.lzb.steps);
    EXPECT_LE(error, 1e-8) << scene;
    EXPECT_LE(relative_momentum_change(model, impact), 1e-12) << scene;
  }
}

TEST(AdaptiveChains, SceneChoosesTheIntegratorAndRefusesTheOtherOnesStep) {
  const std::string path = ::testing::TempDir() + "adaptive_with_delta_p.json";
  std::ofstream(path) << R"({"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
    "chain": {"segments": [{"count": 3, "radius": 0.01}]},
    "strikers": [{"side": "left", "radius": 0.01, "velocity": 1.0}],
    "impact": {"integrator": "adaptive", "tolerance": 1e-8, "delta_p": 1e-6}})";
  try {
    chains::load_chain_scene(path);
    ADD_FAILURE() << "a delta_p with the adaptive integrator was accepted";
  } catch (const InvalidInput& error) {
    EXPECT_NE(std::string(error.what()).find("impact.delta_p = 1e-06"), std::string::npos)
        << error.what();
  }
  plugins::register_plugins();
  EXPECT_THROW(kernel::impact_problems().create("lzb", {{"tolerance", 1e-9}}), InvalidInput);
  EXPECT_THROW(
      kernel::impact_problems().create("lzb", {{"integrator", "adaptive"}, {"delta_p", 1e-7}}),
      InvalidInput);
  EXPECT_THROW(kernel::impact_problems().create("lzb", {{"integrator", "runge-kutta"}}),
               InvalidInput);
}

}  // namespace
}  // namespace mimpact::testing
