#include "mimpact/plugins/register_plugins.hpp"

#include "mimpact/kernel/registry.hpp"
#include "mimpact/plugins/acceleration_lcp_problem.hpp"
#include "mimpact/plugins/compliant_integrator.hpp"
#include "mimpact/plugins/event_driven_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"

namespace mimpact::plugins {

void register_plugins() {
  kernel::integrators().add<EventDrivenIntegrator>("event-driven");
  kernel::integrators().add<CompliantIntegrator>("compliant");
  kernel::impact_problems().add<LzbImpactProblem>("lzb");
  kernel::contact_force_problems().add<AccelerationLcpProblem>("acceleration-lcp");
}

}  // namespace mimpact::plugins
