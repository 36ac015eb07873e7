// The one rule of the LZB impact options (issue 22, item 2): wherever they come from, a step
// given to the adaptive integrator, a tolerance given to the impulse steps and two steps at
// once are refused by name, whatever their values (the default's included), instead of being
// silently ignored or overriding one another.
#include <gtest/gtest.h>

#include "../support/error_of.hpp"
#include "mimpact/kernel/parameters.hpp"
#include "mimpact/kernel/registry.hpp"
#include "mimpact/plugins/lzb_impact_options.hpp"
#include "mimpact/plugins/register_plugins.hpp"

namespace mimpact::plugins {
namespace {

using testing::error_of;

std::string check_error(const LzbImpactOptions& options, const fields::Labels& labels = {}) {
  return error_of([&] { options.check("scene.json", labels); });
}

TEST(LzbImpactOptions, AStepGivenToTheAdaptiveIntegratorIsRefusedWhateverItsValue) {
  for (double delta_p : {LzbImpactOptions::kDefaultDeltaP, 2e-5}) {
    const LzbImpactOptions options{.integrator = LzbIntegrator::adaptive, .delta_p = delta_p};
    EXPECT_EQ(check_error(options, {.prefix = "impact."}),
              "scene.json: impact.delta_p = " + to_text(delta_p) +
                  " chooses the step of the impulse steps, but impact.integrator is "
                  "\"adaptive\"; allowed: impact.tolerance with \"adaptive\", or a step with "
                  "\"impulse-step\" or \"asynchronous\"");
  }
  const LzbImpactOptions relative{.integrator = LzbIntegrator::adaptive, .relative_delta_p = 1e-3};
  EXPECT_NE(check_error(relative).find("relative_delta_p = 0.001 chooses the step"),
            std::string::npos);
}

TEST(LzbImpactOptions, AToleranceGivenToTheImpulseStepsIsRefused) {
  for (auto integrator : {LzbIntegrator::impulse_step, LzbIntegrator::asynchronous}) {
    const LzbImpactOptions options{.integrator = integrator, .tolerance = 1e-8};
    EXPECT_NE(check_error(options).find("tolerance = 1e-08 is the accuracy of the adaptive "
                                        "integrator, but integrator is \"" +
                                        std::string(enum_name(integrator)) + "\""),
              std::string::npos);
  }
  // no integrator named: the impulse steps, which take no tolerance either
  EXPECT_NE(check_error({.tolerance = 1e-8}).find("integrator is \"impulse-step\""),
            std::string::npos);
}

TEST(LzbImpactOptions, TwoStepsAtOnceAreRefused) {
  // relative_delta_p overrode delta_p, and the summary reported delta_p
  EXPECT_EQ(check_error({.delta_p = 1e-5, .relative_delta_p = 1e-3}, {.prefix = "impact."}),
            "scene.json: impact.delta_p = 1e-05 and impact.relative_delta_p = 0.001 both choose "
            "the impulse step; allowed: one of them");
}

TEST(LzbImpactOptions, MessagesNameEachFieldWhereItWasGiven) {
  const fields::Labels labels{.prefix = "impact.", .chosen = {{"delta_p", "--delta-p"}}};
  EXPECT_EQ(check_error({.delta_p = -1.0}, labels),
            "scene.json: --delta-p = -1 is invalid; allowed: > 0 (N s)");
  EXPECT_NE(check_error({.integrator = LzbIntegrator::adaptive, .delta_p = 1e-6}, labels)
                .find("--delta-p = 1e-06 chooses the step of the impulse steps, but "
                      "impact.integrator is \"adaptive\""),
            std::string::npos);
  LzbImpactOptions nested;
  nested.impulse_steps.fixed_thresholds = {.velocity = 0.0, .energy = 1.0};
  EXPECT_EQ(check_error(nested, labels),
            "scene.json: impact.fixed_thresholds.velocity = 0 is invalid; allowed: > 0 (m/s)");
}

TEST(LzbImpactOptions, ConsistentChoicesGiveTheIntegratorsTheirOptions) {
  EXPECT_EQ(check_error({.delta_p = 2e-6}), "");
  EXPECT_EQ(LzbImpactOptions{.delta_p = 2e-6}.impulse_step_options().delta_p, 2e-6);
  EXPECT_EQ(LzbImpactOptions{}.impulse_step_options().delta_p, LzbImpactOptions::kDefaultDeltaP);
  const LzbImpactOptions adaptive{.integrator = LzbIntegrator::adaptive, .tolerance = 1e-9};
  EXPECT_EQ(check_error(adaptive), "");
  EXPECT_EQ(adaptive.adaptive_options().tolerance, 1e-9);
  EXPECT_EQ(adaptive.adaptive_options().max_steps, adaptive.impulse_steps.max_steps);
}

// The registry's parameters go through the same rule: {"integrator": "adaptive", "delta_p":
// 1e-5} was accepted because 1e-5 is the default, and 2e-5 refused.
TEST(LzbImpactOptions, TheRegistryAppliesTheSameRule) {
  register_plugins();
  for (double delta_p : {1e-5, 2e-5})
    EXPECT_NE(error_of([&] {
                kernel::impact_problems().create(
                    "lzb", {{"integrator", "adaptive"}, {"delta_p", delta_p}});
              }).find("delta_p = " + to_text(delta_p) + " chooses the step"),
              std::string::npos);
  EXPECT_NE(
      error_of([&] {
        kernel::impact_problems().create("lzb", {{"delta_p", 1e-5}, {"relative_delta_p", 1e-3}});
      }).find("both choose the impulse step"),
      std::string::npos);
}

}  // namespace
}  // namespace mimpact::plugins
