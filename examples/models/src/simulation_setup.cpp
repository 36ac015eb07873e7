#include "mimpact/models/simulation_setup.hpp"

#include "mimpact/plugins/acceleration_lcp_problem.hpp"

namespace mimpact::models {

kernel::Simulation make_simulation(std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                                   const SimulationSetup& setup) {
  return kernel::Simulation(std::move(system),
                            std::make_unique<plugins::EventDrivenIntegrator>(setup.integrator),
                            std::make_unique<plugins::LzbImpactProblem>(setup.impacts),
                            std::make_unique<plugins::AccelerationLcpProblem>());
}

}  // namespace mimpact::models
