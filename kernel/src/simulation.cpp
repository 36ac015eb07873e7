#include "mimpact/kernel/simulation.hpp"

#include <chrono>
#include <cmath>
#include <optional>

#include "mimpact/common/error.hpp"

namespace mimpact::kernel {

std::string_view to_string(RunStatus status) {
  return status == RunStatus::reached_end ? "reached_end" : "terminated";
}

namespace {

// The problems given must be those the integrator needs: a missing one would fail at the
// first event, an extra one would be silently unused.
void check_problem(bool needed, const OneStepNSProblem* given, std::string_view integrator,
                   const std::string& kind) {
  const std::string who = "Simulation: the one-step integrator \"" + std::string(integrator) + "\"";
  if (needed && !given) throw InvalidInput(who + " needs " + kind + "; none was given");
  if (!needed && given)
    throw InvalidInput(who + " solves no " + kind.substr(kind.find(' ') + 1) + "; \"" +
                       std::string(given->name()) + "\" was given");
}

}  // namespace

Simulation::Simulation(std::shared_ptr<NonSmoothDynamicalSystem> system,
                       std::unique_ptr<OneStepIntegrator> integrator, SimulationProblems problems,
                       SimulationOptions options)
    : system_(std::move(system)),
      integrator_(std::move(integrator)),
      problems_(std::move(problems)),
      options_(options) {
  if (!system_) throw InvalidInput("Simulation: no nonsmooth dynamical system");
  if (!integrator_) throw InvalidInput("Simulation: no one-step integrator");
  const OneStepIntegrator::Needs needs = integrator_->needs();
  check_problem(needs.impacts, problems_.impacts.get(), integrator_->name(), "an impact problem");
  check_problem(needs.contact_forces, problems_.contact_forces.get(), integrator_->name(),
                "a contact force problem");
  validate(options_, "Simulation");
}

namespace {

void check_time(double value, const std::string& what) {
  if (!std::isfinite(value)) throw InvalidInput(invalid_value_message(what, value, "finite (s)"));
}

}  // namespace

void Simulation::add_observer(SimulationObserver& observer) {
  if (running_) throw Error("Simulation: add_observer while the simulation runs");
  observers_.push_back(&observer);
}

void Simulation::schedule_output(double time) {
  if (running_) throw Error("Simulation: schedule_output while the simulation runs");
  check_time(time, "output time");
  outputs_.add(time, 0.0, 1);
}

void Simulation::schedule_outputs(double start, double interval, double end) {
  if (running_) throw Error("Simulation: schedule_outputs while the simulation runs");
  check_time(start, "output start");
  check_time(end, "output end");
  if (!(interval > 0.0 && std::isfinite(interval)))
    throw InvalidInput(invalid_value_message("output interval", interval, "> 0 (s), finite"));
  const double count = std::floor((end - start) / interval + 1e-9);
  if (count > kMostOutputs)
    throw InvalidInput(invalid_value_message("output interval", interval,
                                             ">= (end - start) / " + to_text(kMostOutputs) + " = " +
                                                 to_text((end - start) / kMostOutputs) +
                                                 " s (at most 1e9 outputs)"));
  outputs_.add(start, interval, std::int64_t(count) + 1);
}

namespace {

// Clears `flag` when the call that set it returns or throws.
struct Lowered {
  std::atomic<bool>& flag;
  ~Lowered() { flag = false; }
};

void refuse_reentry(std::atomic<bool>& running, const char* what) {
  if (running.exchange(true))
    throw Error(std::string("Simulation::") + what +
                ": the simulation is already running (from another thread, or run again by one "
                "of its observers); allowed: one run at a time");
}

}  // namespace

void Simulation::initialize(double start) {
  check_time(start, "start time");
  refuse_reentry(running_, "initialize");
  Lowered lowered{running_};
  start_at(start);
}

bool Simulation::advance_to(double end) {
  check_time(end, "end time");
  if (!initialized_) throw Error("Simulation::advance_to before initialize");
  if (!(end >= time_))
    throw InvalidInput(invalid_value_message("end time", end, ">= the time " + to_text(time_)));
  refuse_reentry(running_, "advance_to");
  Lowered lowered{running_};
  return advance(end);
}

RunSummary Simulation::finish() {
  if (!initialized_) throw Error("Simulation::finish before initialize");
  refuse_reentry(running_, "finish");
  Lowered lowered{running_};
  return end_run();
}

RunSummary Simulation::run(double start, double end) {
  check_time(start, "start time");
  check_time(end, "end time");
  if (!(end >= start))
    throw InvalidInput(
        invalid_value_message("end time", end, ">= the start time " + to_text(start)));
  refuse_reentry(running_, "run");
  Lowered lowered{running_};
  start_at(start);
  advance(end);
  return end_run();
}

void Simulation::start_at(double start) {
  if (problems_.impacts)
    for (Index j = 0; j < system_->interaction_count(); ++j)
      problems_.impacts->check_law(system_->interaction(j).law(), system_->interaction(j).name());
  system_->check(options_.penetration_tolerance);

  clock_start_ = std::chrono::steady_clock::now();
  summary_ = {};
  summary_.start_time = start;
  termination_.reset();
  time_ = start;
  integrator_->initialize(*system_, start,
                          {problems_.impacts.get(), problems_.contact_forces.get()});
  initialized_ = true;
  tell([&](SimulationObserver& o) { o.on_start(*this); });
  // outputs before the start are past; those at the start need no advance
  while (!outputs_.empty() && outputs_.next() <= start) {
    if (outputs_.next() == start) tell([&](SimulationObserver& o) { o.on_output(*this); });
    outputs_.pop();
  }
}

bool Simulation::advance(double end) {
  while (time_ < end && !termination_) {
    const double target = outputs_.empty() ? end : std::min(end, outputs_.next());
    const StepReport step = integrator_->advance(target);
    time_ = step.time;
    ++summary_.advances;
    summary_.smooth_steps += step.smooth_steps;
    tell([&](SimulationObserver& o) {
      EventStatus status = o.on_step(*this, step);
      if (status.terminates() && !termination_) termination_ = std::move(status);
    });
    if (step.event) {
      ++summary_.events;
      tell([&](SimulationObserver& o) { o.on_event(*this, step); });
      if (step.impact) {
        ++summary_.impacts;
        tell([&](SimulationObserver& o) { o.on_impact(*this, *step.impact); });
      }
    }
    while (!outputs_.empty() && outputs_.next() <= time_) {
      outputs_.pop();
      tell([&](SimulationObserver& o) { o.on_output(*this); });
    }
  }
  return !termination_;
}

RunSummary Simulation::end_run() {
  initialized_ = false;
  if (termination_) {
    summary_.status = RunStatus::terminated;
    summary_.reason = termination_->reason();
  }
  summary_.end_time = time_;
  summary_.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - clock_start_).count();
  tell([&](SimulationObserver& o) { o.on_end(*this); });
  return summary_;
}

}  // namespace mimpact::kernel
