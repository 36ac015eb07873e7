#pragma once

#include "mimpact/kernel/simulation.hpp"

namespace mimpact::testing {

// Ends a run where a contact opens: a single strike's outcome.
struct StopWhenAContactOpens : kernel::SimulationObserver {
  kernel::EventStatus on_step(const kernel::Simulation&, const kernel::StepReport& step) override {
    return step.detaching.empty() ? kernel::EventStatus::proceed()
                                  : kernel::EventStatus::terminate("the contact has opened");
  }
};

}  // namespace mimpact::testing
