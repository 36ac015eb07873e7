#include "mimpact/models/simulation_setup.hpp"

#include "mimpact/common/error.hpp"
#include "mimpact/kernel/parameters.hpp"
#include "mimpact/kernel/registry.hpp"
#include "mimpact/plugins/register_plugins.hpp"

namespace mimpact::models {

plugins::LzbImpactOptions impact_options_from_command_line(
    int argc, const char* const argv[], const plugins::LzbImpactOptions& defaults) {
  if (argc <= 1) return defaults;
  if (argc > 2)
    throw InvalidInput(std::string(argv[0]) + ": " + std::to_string(argc - 1) +
                       " arguments; allowed: none, or one JSON object of the impact options");
  const kernel::Parameters parameters =
      kernel::Parameters::parse(argv[1], nullptr, /*allow_exceptions=*/false);
  if (parameters.is_discarded())
    throw InvalidInput(std::string(argv[0]) + ": the argument '" + argv[1] +
                       "' is not JSON; allowed: an object such as "
                       "'{\"integrator\": \"adaptive\", \"tolerance\": 1e-10}'");
  plugins::LzbImpactOptions options = kernel::options_from<plugins::LzbImpactOptions>(
      parameters, {.name = std::string(argv[0]) + " impact options"});
  plugins::LzbImpactProblem checked(options);  // refuses options of the integrator not chosen
  return options;
}

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
