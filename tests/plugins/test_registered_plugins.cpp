// The plugins are chosen by name through the kernel's registries.
#include <gtest/gtest.h>

#include <string>

#include "mimpact/kernel/registry.hpp"
#include "mimpact/plugins/event_driven_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"
#include "mimpact/numerics/error.hpp"
#include "mimpact/plugins/register_plugins.hpp"

namespace mimpact::plugins {
namespace {

TEST(RegisteredPlugins, CreatedByNameWithTheirParameters) {
  register_plugins();
  auto integrator = kernel::integrators().create("event-driven", {{"event_tolerance", 1e-12}});
  EXPECT_EQ(integrator->name(), "event-driven");
  EXPECT_EQ(dynamic_cast<EventDrivenIntegrator&>(*integrator).options().event_tolerance, 1e-12);

  auto impacts = kernel::impact_problems().create("lzb", {{"delta_p", 1e-7}, {"dense_up_to", 4}});
  const auto& lzb = dynamic_cast<LzbImpactProblem&>(*impacts);
  EXPECT_EQ(lzb.options().integrator.delta_p, 1e-7);
  EXPECT_EQ(lzb.options().dense_up_to, 4);

  EXPECT_EQ(kernel::contact_force_problems().create("acceleration-lcp")->name(), "acceleration-lcp");
  EXPECT_THROW(kernel::impact_problems().create("lzb", {{"deltap", 1e-7}}), InvalidInput);
  EXPECT_THROW(kernel::impact_problems().create("lzb", {{"delta_p", -1.0}}), InvalidInput);
  EXPECT_THROW(kernel::integrators().create("time-stepping"), InvalidInput);
}

// Integer parameters travel as doubles: a fraction or a value past the type is named, not
// truncated or wrapped.
TEST(RegisteredPlugins, IntegerParametersMustBeWholeAndInRange) {
  register_plugins();
  auto expect_named = [](auto create, const std::string& message) {
    try {
      create();
      ADD_FAILURE() << "no error for " << message;
    } catch (const InvalidInput& error) {
      EXPECT_NE(std::string(error.what()).find(message), std::string::npos) << error.what();
    }
  };
  expect_named([] { kernel::impact_problems().create("lzb", {{"dense_up_to", 2.7}}); },
               "dense_up_to = 2.7 is invalid; allowed: an integer in [0, ");
  expect_named([] { kernel::impact_problems().create("lzb", {{"max_steps", 1e300}}); },
               "max_steps = 1e+300 is invalid");
  expect_named([] { kernel::integrators().create("event-driven", {{"samples_per_step", 0.5}}); },
               "samples_per_step = 0.5 is invalid");
  expect_named([] { kernel::contact_force_problems().create("acceleration-lcp", {{"max_pivots", -1}}); },
               "max_pivots = -1 is invalid");
  auto impacts = kernel::impact_problems().create("lzb", {{"max_steps", 1e6}});
  EXPECT_EQ(dynamic_cast<LzbImpactProblem&>(*impacts).options().integrator.max_steps, 1'000'000);
}

}  // namespace
}  // namespace mimpact::plugins
