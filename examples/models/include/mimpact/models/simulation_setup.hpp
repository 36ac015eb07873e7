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

// An example program's impact options from its command line: no argument keeps `defaults`; one
// argument is a JSON object of the "lzb" impact problem's fields, which replaces them, e.g.
// '{"integrator": "adaptive", "tolerance": 1e-10}' or '{"relative_delta_p": 1e-5}'. Throws
// InvalidInput naming the field, its value and what is allowed.
plugins::LzbImpactOptions impact_options_from_command_line(
    int argc, const char* const argv[], const plugins::LzbImpactOptions& defaults);

kernel::Simulation make_simulation(std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                                   const SimulationSetup& setup = {});

}  // namespace mimpact::models
