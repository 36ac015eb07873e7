#include "mimpact/kernel/simulation.hpp"

#include <chrono>
#include <cmath>

#include "mimpact/numerics/error.hpp"

namespace mimpact::kernel {

std::string_view to_string(RunStatus status) {
  return status == RunStatus::reached_end ? "reached_end" : "stopped";
}

Simulation::Simulation(std::shared_ptr<NonSmoothDynamicalSystem> system,
                       std::unique_ptr<OneStepIntegrator> integrator,
                       std::unique_ptr<ImpactProblem> impacts,
                       std::unique_ptr<ContactForceProblem> forces, SimulationOptions options)
    : system_(std::move(system)),
      integrator_(std::move(integrator)),
      impacts_(std::move(impacts)),
      forces_(std::move(forces)),
      options_(options) {
  if (!system_) throw InvalidInput("Simulation: no nonsmooth dynamical system");
  if (!integrator_) throw InvalidInput("Simulation: no one-step integrator");
  if (!impacts_) throw InvalidInput("Simulation: no impact problem");
  if (!forces_) throw InvalidInput("Simulation: no contact force problem");
  if (!(options_.penetration_tolerance >= 0.0))
    throw InvalidInput(invalid_value_message("penetration_tolerance",
                                             options_.penetration_tolerance, ">= 0 (m)"));
}

void Simulation::schedule_outputs(double start, double interval, double end) {
  if (!(interval > 0.0))
    throw InvalidInput(invalid_value_message("output interval", interval, "> 0 (s)"));
  const auto count = std::int64_t(std::floor((end - start) / interval + 1e-9));
  for (std::int64_t k = 0; k <= count; ++k) outputs_.push(start + double(k) * interval);
}

RunSummary Simulation::run(double start, double end) {
  if (!(end >= start))
    throw InvalidInput(invalid_value_message("end time", end, ">= the start time " + to_text(start)));
  for (Index j = 0; j < system_->interaction_count(); ++j)
    impacts_->check_law(system_->interaction(j).law(), system_->interaction(j).name());
  system_->check(options_.penetration_tolerance);

  const auto clock_start = std::chrono::steady_clock::now();
  RunSummary summary;
  summary.start_time = start;
  time_ = start;
  stop_requested_ = false;
  integrator_->initialize(*system_, start, *impacts_, *forces_);
  tell([&](SimulationObserver& o) { o.on_start(*this); });
  // outputs before the start are past; those at the start need no advance
  while (!outputs_.empty() && outputs_.top() <= start) {
    if (outputs_.top() == start) tell([&](SimulationObserver& o) { o.on_output(*this); });
    outputs_.pop();
  }

  while (time_ < end && !stop_requested_) {
    const double target = outputs_.empty() ? end : std::min(end, outputs_.top());
    const StepReport step = integrator_->advance(target);
    time_ = step.time;
    ++summary.advances;
    summary.smooth_steps += step.smooth_steps;
    tell([&](SimulationObserver& o) { o.on_step(*this, step); });
    if (step.event) {
      ++summary.events;
      tell([&](SimulationObserver& o) { o.on_event(*this, step); });
      if (step.impact) {
        ++summary.impacts;
        tell([&](SimulationObserver& o) { o.on_impact(*this, *step.impact); });
      }
    }
    while (!outputs_.empty() && outputs_.top() <= time_) {
      outputs_.pop();
      tell([&](SimulationObserver& o) { o.on_output(*this); });
    }
  }
  summary.status = stop_requested_ ? RunStatus::stopped : RunStatus::reached_end;
  summary.end_time = time_;
  summary.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - clock_start).count();
  tell([&](SimulationObserver& o) { o.on_end(*this); });
  return summary;
}

}  // namespace mimpact::kernel
