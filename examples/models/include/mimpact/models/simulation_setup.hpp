#pragma once

#include <memory>

#include "mimpact/kernel/simulation.hpp"
#include "mimpact/plugins/event_driven_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"

namespace mimpact::models {

// The usual pairing: the event-driven integrator, the LZB impact problem and the
// acceleration-level LCP, over `system`.
struct SimulationSetup {
  plugins::EventDrivenOptions integrator;
  plugins::LzbImpactOptions impacts;
};

kernel::Simulation make_simulation(std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                                   const SimulationSetup& setup = {});

}  // namespace mimpact::models
