#include "mimpact/models/simulation_setup.hpp"

#include "mimpact/kernel/registry.hpp"
#include "mimpact/plugins/register_plugins.hpp"

namespace mimpact::models {

kernel::Simulation make_simulation(std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                                   const SimulationSetup& setup) {
  plugins::register_plugins();
  return kernel::Simulation(
      std::move(system),
      kernel::integrators().create("event-driven", kernel::to_parameters(setup.integrator)),
      {.impacts = kernel::impact_problems().create("lzb", kernel::to_parameters(setup.impacts)),
       .contact_forces = kernel::contact_force_problems().create("acceleration-lcp")});
}

}  // namespace mimpact::models
