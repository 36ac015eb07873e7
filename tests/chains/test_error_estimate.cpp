// A run's estimate of its own error (granular/error_estimate.hpp, docs/design/error_estimates.md):
// on C1 by each method, against the true error (the run at a step 1 000 times finer), the
// estimate bounds it and is within ten times it. Issue 48 asks this of 95 % and 90 % of a corpus
// of 40 scenes (tests/packings/test_error_corpus.cpp); these are C1's, and a long chain's
// accuracy.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>

#include "mimpact/chains/chain_model.hpp"
#include "mimpact/chains/chain_run.hpp"
#include "mimpact/chains/chain_scene.hpp"
#include "mimpact/common/error.hpp"

namespace mimpact::testing {
namespace {

// C1 (examples/scenes/c1.json) at restitution e, run as `how` says.
chains::ChainScene c1(double restitution, const std::string& how) {
  char text[512];
  std::snprintf(text, sizeof text, R"({
    "material": {"density": 7780, "young": 203e9, "poisson": 0.3},
    "chain": {"segments": [{"count": 20, "radius": 0.010}]},
    "strikers": [{"side": "left", "radius": 0.010, "velocity": 1.0}],
    "contact": {"model": "bi-stiffness", "exponent": 1.5, "restitution": %g}, %s})",
                restitution, how.c_str());
  return chains::parse_chain_scene(text, "C1");
}

struct Estimated {
  double estimate = 0.0, truth = 0.0;  // RMS over the beads, of the striker's 1 m/s
};

// The scene's run with its estimate, and the true RMS error against `reference`.
Estimated estimated(const chains::ChainScene& scene, const chains::ChainScene& reference) {
  const chains::ChainModel model = chains::build_chain_model(scene);
  const granular::SceneRun run = chains::run_chain_scene(scene, model, {.estimate_error = true});
  const granular::SceneRun exact = chains::run_chain_scene(reference, model);
  const Eigen::VectorXd error = run.impact.velocity_after - exact.impact.velocity_after;
  EXPECT_TRUE(run.error_estimate.has_value());
  EXPECT_EQ(chains::run_summary(model, run)["error_estimate"]["rms"].get<double>(),
            run.error_estimate->rms);
  const Estimated result{run.error_estimate->rms,
                         std::sqrt(error.squaredNorm() / double(error.size()))};
  std::printf("%-60s estimate %.3g, true %.3g (x %.3g); %s\n", scene.source.c_str(),
              result.estimate, result.truth, result.estimate / result.truth,
              run.error_estimate->method.c_str());
  return result;
}

std::string label(const char* what, double value, double tolerance = 0.0) {
  char text[96];
  std::snprintf(text, sizeof text, tolerance > 0.0 ? "%s %g, tolerance %g" : "%s %g", what, value,
                tolerance);
  return text;
}

void expect_honest(const Estimated& estimated, const std::string& what) {
  EXPECT_GE(estimated.estimate, estimated.truth) << what;
  EXPECT_LE(estimated.estimate, 10.0 * estimated.truth) << what;
}

std::string impact(const char* field, double value, const char* integrator = "") {
  char text[160];
  std::snprintf(text, sizeof text, R"("impact": {%s"%s": %g})", integrator, field, value);
  return text;
}

TEST(ErrorEstimate, ImpulseStepsByRichardsonOverDeltaP) {
  for (double delta_p : {1e-4, 1e-5}) {
    chains::ChainScene scene = c1(1.0, impact("delta_p", delta_p));
    scene.source = label("impulse steps, delta_p", delta_p);
    expect_honest(estimated(scene, c1(1.0, impact("delta_p", delta_p / 1000))), scene.source);
  }
}

TEST(ErrorEstimate, AdaptiveLzbByACompanionAtAFifthOfTheTolerance) {
  for (double e : {1.0, 0.9, 0.5})
    for (double tolerance : {1e-4, 1e-6, 1e-8}) {
      const char* adaptive = R"("integrator": "adaptive", )";
      chains::ChainScene scene = c1(e, impact("tolerance", tolerance, adaptive));
      scene.source = label("adaptive, e", e, tolerance);
      expect_honest(estimated(scene, c1(e, impact("tolerance", tolerance / 1000, adaptive))),
                    scene.source);
    }
}

TEST(ErrorEstimate, CompliantContactsByACompanionAtAFifthOfTheTolerance) {
  auto compliant = [](double tolerance) {
    char text[96];
    std::snprintf(text, sizeof text, R"("method": "compliant", "compliant": {"tolerance": %g})",
                  tolerance);
    return std::string(text);
  };
  for (double e : {1.0, 0.9, 0.5})
    for (double tolerance : {1e-5, 1e-7}) {
      chains::ChainScene scene = c1(e, compliant(tolerance));
      scene.source = label("compliant, e", e, tolerance);
      expect_honest(estimated(scene, c1(e, compliant(tolerance / 1000))), scene.source);
    }
}

// The least max_steps (compliant.max_steps, or impact.max_steps) with which `scene` runs.
std::int64_t least_budget(chains::ChainScene scene, const chains::ChainModel& model) {
  std::int64_t fails = 1, runs = 1 << 20;  // bisected: fails < least <= runs
  while (runs - fails > 1) {
    const std::int64_t budget = (fails + runs) / 2;
    scene.compliant.max_steps = scene.impact.impulse_steps.max_steps = budget;
    try {
      chains::run_chain_scene(scene, model);
      runs = budget;
    } catch (const std::exception&) {
      fails = budget;
    }
  }
  return runs;
}

// A finer companion takes more steps than its run: a run within its budget of steps is not
// refused for its estimate.
TEST(ErrorEstimate, AFinerCompanionHasTheStepsItNeeds) {
  for (const char* how : {R"("method": "compliant", "compliant": {"tolerance": 1e-6})",
                          R"("impact": {"integrator": "adaptive", "tolerance": 1e-6})"}) {
    chains::ChainScene scene = c1(0.9, how);
    const chains::ChainModel model = chains::build_chain_model(scene);
    const std::int64_t budget = least_budget(scene, model);
    scene.compliant.max_steps = scene.impact.impulse_steps.max_steps = budget;
    const granular::SceneRun run = chains::run_chain_scene(scene, model, {.estimate_error = true});
    ASSERT_TRUE(run.error_estimate) << how;
    EXPECT_LT(run.error_estimate->worst, 1e-4) << how;
  }
}

// Beside its run on a second thread or after it (RunLimits::threads), a companion gives the same
// answer and the same estimate, to the last bit, by each method and asked for an accuracy.
TEST(ErrorEstimate, BesideTheRunOrAfterItTheSameEstimate) {
  for (const char* how : {R"("impact": {"delta_p": 1e-5})",
                          R"("impact": {"integrator": "adaptive", "tolerance": 1e-6})",
                          R"("method": "compliant", "compliant": {"tolerance": 1e-6})",
                          R"("method": "compliant", "accuracy": 1e-6)",
                          R"("impact": {"integrator": "impulse-step"}, "accuracy": 1e-4)"}) {
    const chains::ChainScene scene = c1(0.9, how);
    const chains::ChainModel model = chains::build_chain_model(scene);
    granular::SceneRun runs[2];
    for (int threads : {1, 2})
      runs[threads - 1] = chains::run_chain_scene(
          scene, model, {.limits = {.threads = threads}, .estimate_error = true});
    ASSERT_TRUE(runs[0].error_estimate && runs[1].error_estimate) << how;
    EXPECT_EQ(runs[0].impact.velocity_after, runs[1].impact.velocity_after) << how;
    EXPECT_EQ(runs[0].error_estimate->worst, runs[1].error_estimate->worst) << how;
    EXPECT_EQ(runs[0].error_estimate->rms, runs[1].error_estimate->rms) << how;
    EXPECT_EQ(runs[0].accuracy.has_value(), runs[1].accuracy.has_value()) << how;
    if (runs[0].accuracy) {
      EXPECT_EQ(runs[0].accuracy->runs, runs[1].accuracy->runs) << how;
    }
  }
}

// A run that fails beside its companion raises its own failure: C1 by the compliant contacts
// with one step fewer than it needs, its companion allowed four times as many.
TEST(ErrorEstimate, ARunsOwnFailureIsRaisedBesideItsCompanion) {
  chains::ChainScene scene = c1(0.9, R"("method": "compliant", "compliant": {"tolerance": 1e-6})");
  const chains::ChainModel model = chains::build_chain_model(scene);
  scene.compliant.max_steps = least_budget(scene, model) - 1;
  try {
    chains::run_chain_scene(scene, model, {.limits = {.threads = 2}, .estimate_error = true});
    ADD_FAILURE() << "a run short of its steps ran";
  } catch (const Error& failed) {
    EXPECT_NE(std::string(failed.what()).find(std::to_string(scene.compliant.max_steps)),
              std::string::npos)
        << failed.what();
  }
}

// The worst body's true error of a run asked for `accuracy` (the scene's "accuracy"), against
// the same method at a step 1 000 times finer than the one the run chose.
double worst_true_error(const std::string& how, double accuracy, const char* step_field) {
  char text[160];
  std::snprintf(text, sizeof text, R"(%s, "accuracy": %g)", how.c_str(), accuracy);
  const chains::ChainScene scene = c1(1.0, text);
  const chains::ChainModel model = chains::build_chain_model(scene);
  const granular::SceneRun run = chains::run_chain_scene(scene, model);
  EXPECT_TRUE(run.accuracy && run.accuracy->met) << text;
  EXPECT_LE(run.error_estimate->worst, accuracy) << text;
  EXPECT_EQ(run.accuracy->step, step_field);
  // the impulse steps' limit is the adaptive integrator's (docs/model.md, section 10): at a
  // tolerance of 1e-12 it stands for delta_p 1 000 times finer at a thousandth of the cost
  chains::ChainScene reference = scene;
  reference.accuracy.reset();
  if (scene.method == granular::Method::compliant) {
    reference.compliant.tolerance = run.accuracy->value / 1000.0;
  } else {
    reference.impact.integrator = plugins::LzbIntegrator::adaptive;
    reference.impact.tolerance =
        std::string(step_field) == "delta_p" ? 1e-12 : std::max(run.accuracy->value / 1000, 1e-13);
  }
  const Eigen::VectorXd exact = chains::run_chain_scene(reference, model).impact.velocity_after;
  double worst = 0.0;
  for (Eigen::Index b = 0; b < exact.size(); ++b)
    worst = std::max(worst, std::abs(run.impact.velocity_after[b] - exact[b]));
  std::printf("%s: accuracy %g, %s %.3g in %d runs: estimate %.3g, true %.3g\n", how.c_str(),
              accuracy, step_field, run.accuracy->value, run.accuracy->runs,
              run.error_estimate->worst, worst);
  return worst;  // of the striker's 1 m/s
}

TEST(Accuracy, EachMethodChoosesAStepThatMeetsIt) {
  for (double accuracy : {1e-4, 1e-6}) {
    EXPECT_LE(worst_true_error(R"("impact": {"integrator": "impulse-step"})", accuracy, "delta_p"),
              accuracy);
    EXPECT_LE(worst_true_error(R"("impact": {"integrator": "adaptive"})", accuracy, "tolerance"),
              accuracy);
    EXPECT_LE(worst_true_error(R"("method": "compliant")", accuracy, "tolerance"), accuracy);
  }
}

// The last bead's error grows with the chain's length: on 10 000 beads a tolerance equal to the
// accuracy misses it by about 40 times, and the first pair starts at accuracy x 100 / bodies
// (granular::first_step) instead, so that it meets the accuracy by itself: two runs.
TEST(Accuracy, ALongChainsFirstPairMeetsIt) {
  for (const char* how : {R"("impact": {"integrator": "adaptive"})", R"("method": "compliant")"}) {
    char text[512];
    std::snprintf(text, sizeof text, R"({
      "material": {"density": 7780, "young": 203e9, "poisson": 0.3},
      "chain": {"segments": [{"count": 10000, "radius": 0.010}]},
      "strikers": [{"side": "left", "radius": 0.010, "velocity": 1.0}],
      "contact": {"model": "bi-stiffness", "exponent": 1.5, "restitution": 1.0},
      "accuracy": 1e-4, %s})",
                  how);
    const chains::ChainScene scene = chains::parse_chain_scene(text, "10 000 beads");
    const chains::ChainModel model = chains::build_chain_model(scene);
    const granular::SceneRun run = chains::run_chain_scene(scene, model);
    ASSERT_TRUE(run.accuracy && run.accuracy->met) << how;
    EXPECT_EQ(run.accuracy->runs, 2) << how;
    chains::ChainScene reference = scene;
    reference.accuracy.reset();
    if (scene.method == granular::Method::compliant)
      reference.compliant.tolerance = run.accuracy->value / 1000.0;
    else
      reference.impact.tolerance = run.accuracy->value / 1000.0;
    const Eigen::VectorXd exact = chains::run_chain_scene(reference, model).impact.velocity_after;
    const double truth = (run.impact.velocity_after - exact).cwiseAbs().maxCoeff();
    std::printf("%s: tolerance %.3g in %d runs, estimate %.3g, true %.3g\n", how,
                run.accuracy->value, run.accuracy->runs, run.error_estimate->worst, truth);
    EXPECT_LE(truth, run.error_estimate->worst) << how;
    EXPECT_LE(truth, 1e-4) << how;
  }
}

// Asked for more than its budget of steps allows, a run answers with the last run that has an
// estimate and says the accuracy is NOT met, and why: C1 at e = 0.5 by the compliant contacts
// meets 1e-10 in four runs, its answer at a tolerance of about 2e-12 (21 632 steps); with 15 000
// steps allowed, the first pair (1e-10: 10 610 steps, its companion 14 038 of the four times as
// many it is allowed) is the answer, as a run at its tolerance gives it, its estimate above the
// accuracy and at least its true error.
TEST(Accuracy, ARunPastItsBudgetAnswersWithTheRunBeforeNotMet) {
  const chains::ChainScene scene =
      c1(0.5, R"("method": "compliant", "compliant": {"max_steps": 15000}, "accuracy": 1e-10)");
  const chains::ChainModel model = chains::build_chain_model(scene);
  for (int threads : {1, 2}) {
    granular::SceneRunOptions options;
    options.limits.threads = threads;
    const granular::SceneRun run = chains::run_chain_scene(scene, model, options);
    ASSERT_TRUE(run.accuracy.has_value());
    EXPECT_FALSE(run.accuracy->met);
    EXPECT_NE(run.accuracy->ended.find("finer than tolerance 1e-10 spent its budget of steps: "
                                       "compliant integrator: max_steps = 15000"),
              std::string::npos)
        << run.accuracy->ended;
    EXPECT_GT(run.error_estimate->worst, 1e-10);
    EXPECT_EQ(run.accuracy->value, 1e-10);
    chains::ChainScene alone = scene;
    alone.accuracy.reset();
    alone.compliant.tolerance = 1e-10;
    EXPECT_EQ(run.impact.velocity_after,
              chains::run_chain_scene(alone, model).impact.velocity_after);
    alone.compliant.tolerance = 1e-13;
    alone.compliant.max_steps = 100000;
    const Eigen::VectorXd exact = chains::run_chain_scene(alone, model).impact.velocity_after;
    const double truth = (run.impact.velocity_after - exact).cwiseAbs().maxCoeff();
    std::printf("threads %d: NOT met in %d runs, estimate %.3g, true %.3g; %s\n", threads,
                run.accuracy->runs, run.error_estimate->worst, truth, run.accuracy->ended.c_str());
    EXPECT_LE(truth, run.error_estimate->worst);
    EXPECT_EQ(chains::run_summary(model, run)["accuracy"]["ended"], run.accuracy->ended);
  }
}

TEST(Accuracy, IsAloneWithTheStepRuleInAScene) {
  for (const char* how : {R"("impact": {"delta_p": 1e-5}, "accuracy": 1e-4)",
                          R"("impact": {"tolerance": 1e-5}, "accuracy": 1e-4)",
                          R"("compliant": {"tolerance": 1e-5}, "accuracy": 1e-4)"}) {
    try {
      c1(1.0, how);
      ADD_FAILURE() << how << " was taken";
    } catch (const InvalidInput& error) {
      EXPECT_NE(std::string(error.what()).find("beside accuracy = 0.0001"), std::string::npos)
          << error.what();
    }
  }
}

}  // namespace
}  // namespace mimpact::testing
