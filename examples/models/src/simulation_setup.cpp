#include "mimpact/models/simulation_setup.hpp"

#include "mimpact/common/error.hpp"
#include "mimpact/kernel/json_document.hpp"
#include "mimpact/kernel/parameters.hpp"
#include "mimpact/plugins/acceleration_lcp_problem.hpp"
#include "mimpact/plugins/event_driven_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"

namespace mimpact::models {

plugins::LzbImpactOptions impact_options_from_command_line(
    int argc, const char* const argv[], const plugins::LzbImpactOptions& defaults) {
  if (argc <= 1) return defaults;
  if (argc > 2)
    throw InvalidInput(std::string(argv[0]) + ": " + std::to_string(argc - 1) +
                       " arguments; allowed: none, or one JSON object of the impact options");
  const std::string source = std::string(argv[0]) + " impact options";
  const kernel::JsonDocument parameters = kernel::parse_json_document(argv[1], source);
  plugins::LzbImpactOptions options = kernel::options_from<plugins::LzbImpactOptions>(
      parameters.value, {.name = source, .locations = &parameters.locations});
  options.check(source);  // refuses options of the integrator not chosen
  return options;
}

kernel::Simulation make_simulation(std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                                   const SimulationSetup& setup) {
  return kernel::Simulation(
      std::move(system), std::make_unique<plugins::EventDrivenIntegrator>(setup.integrator),
      {.impacts = std::make_unique<plugins::LzbImpactProblem>(setup.impacts),
       .contact_forces = std::make_unique<plugins::AccelerationLcpProblem>()});
}

}  // namespace mimpact::models
