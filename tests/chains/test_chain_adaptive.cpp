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

// Issue 10 (a): for e = 1 the continuous LZB impact is the Hertz chain; at tolerance 1e-10
// the adaptive integrator is within 1e-8 of the tests' own integration in time.
TEST(AdaptiveChains, ElasticChainsAreTheExactHertzChain) {
  for (const char* scene : {"c1.json", "c2.json"}) {
    const chains::ChainModel model = scene_model(scene);
    const granular::ImpactOutcome impact = run_adaptive(model, 1e-10);
    ASSERT_EQ(impact.result.status, numerics::ImpactStatus::terminated);
    const Eigen::VectorXd exact =
        integrate_hertz_chain(model.mass, model.velocity, stiffnesses(model)).velocity;
    const double error = relative_difference(impact.velocity_after, exact);
    std::printf("%s, adaptive at 1e-10: ||v+ - v+_Hertz|| / ||v+_Hertz|| = %.2g in %lld steps\n",
                scene, error, (long long)impact.result.steps);
    EXPECT_LE(error, 1e-8) << scene;
    EXPECT_LE(relative_momentum_change(model, impact), 1e-12) << scene;
  }
}

struct SameModelCase {
  const char* scene;
  double finest_delta_p;  // N s; the impulse steps run at twice it and at it
  bool mono_stiffness;    // the scene's law turned mono-stiffness
};

// 2 x_h - x_2h: the impulse steps are first order in delta_p (docs/model.md, section 6).
Eigen::VectorXd richardson(const Eigen::VectorXd& fine, const Eigen::VectorXd& coarse) {
  return 2.0 * fine - coarse;
}

// Issue 10 (b): the adaptive integrator at tolerance 1e-10 integrates the same model as the
// seed's impulse steps; their Richardson extrapolation from the two finest steps meets it to
// 1e-5 relative, in the post-impact velocities and in every contact's peak force. The finest
// steps are those where the impulse steps' error has become first order: with e < 1 the
// ends of the contacts' unloading and the impact's termination add an error that is not
// smooth in delta_p above them (C3 and the colliding waves: down to 1e-8 N s).
TEST(AdaptiveChains, SameModelAsTheImpulseStepsExtrapolated) {
  const std::vector<SameModelCase> cases = {{"c1.json", 1e-6, false},
                                            {"c2.json", 5e-7, false},
                                            {"c3.json", 1.25e-8, false},
                                            {"c3.json", 1.25e-8, true},
                                            {"paper/nakagawa_e0955.json", 2.5e-8, false},
                                            {"paper/melo_type2_q1.json", 1.25e-7, false},
                                            {"paper/s25_collision.json", 3.125e-8, false}};
  for (const SameModelCase& c : cases) {
    chains::ChainModel model = scene_model(c.scene);
    if (c.mono_stiffness)
      for (numerics::ContactLaw& law : model.laws)
        law.model = numerics::ComplianceModel::mono_stiffness;
    const std::string name = std::string(c.scene) + (c.mono_stiffness ? " (mono)" : "");
    const granular::ImpactOutcome coarse = run_chain(model, 2.0 * c.finest_delta_p);
    const granular::ImpactOutcome fine = run_chain(model, c.finest_delta_p);
    const granular::ImpactOutcome adaptive = run_adaptive(model, 1e-10);
    ASSERT_EQ(adaptive.result.status, numerics::ImpactStatus::terminated) << name;
    const double velocity_gap = relative_difference(
        adaptive.velocity_after, richardson(fine.velocity_after, coarse.velocity_after));
    const double force_gap = relative_difference(
        adaptive.result.max_force, richardson(fine.result.max_force, coarse.result.max_force));
    std::printf(
        "%-28s impulse steps %lld + %lld, adaptive %lld steps: velocities %.2g, peak forces "
        "%.2g from Richardson (unextrapolated %.2g, %.2g)\n",
        name.c_str(), (long long)coarse.result.steps, (long long)fine.result.steps,
        (long long)adaptive.result.steps, velocity_gap, force_gap,
        relative_difference(adaptive.velocity_after, fine.velocity_after),
        relative_difference(adaptive.result.max_force, fine.result.max_force));
    EXPECT_LE(velocity_gap, 1e-5) << name;
    EXPECT_LE(force_gap, 1e-5) << name;
    EXPECT_LE(relative_momentum_change(model, adaptive), 1e-12) << name;
    if (std::string(c.scene) == "c3.json") {  // the chain locks into one block at V/21
      const double block_speed = model.velocity(0) / double(model.body_count());
      EXPECT_LE((adaptive.velocity_after.array() - block_speed).abs().maxCoeff(),
                1e-8 * block_speed)
          << name;
    }
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
