// The plugins are chosen by name through the kernel's registries.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace mimpact::plugins
