#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mimpact/common/fields.hpp"
#include "mimpact/kernel/event_status.hpp"
#include "mimpact/kernel/non_smooth_dynamical_system.hpp"
#include "mimpact/kernel/one_step_integrator.hpp"
#include "mimpact/kernel/one_step_ns_problem.hpp"
#include "mimpact/kernel/output_times.hpp"

namespace mimpact::kernel {

class Simulation;

// Called by Simulation::run. Every method does nothing unless overridden.
class SimulationObserver {
 public:
  virtual ~SimulationObserver() = default;
  virtual void on_start(const Simulation&) {}
  // After every advance. Answering EventStatus::terminate ends the run once the calls of
  // this advance (on_event, on_impact, on_output) are made.
  virtual EventStatus on_step(const Simulation&, const StepReport&) {
    return EventStatus::proceed();
  }
  virtual void on_event(const Simulation&, const StepReport&) {}     // nonsmooth events
  virtual void on_impact(const Simulation&, const ImpactReport&) {}  // impacts among them
  virtual void on_output(const Simulation&) {}                       // scheduled output times
  virtual void on_end(const Simulation&) {}
};

enum class RunStatus {
  reached_end,  // the end time was reached
  terminated,   // an observer answered EventStatus::terminate
};

std::string_view to_string(RunStatus status);

struct RunSummary {
  RunStatus status = RunStatus::reached_end;
  std::string reason;                       // the observer's, when it terminated the run
  double start_time = 0.0, end_time = 0.0;  // s
  std::int64_t advances = 0;                // calls to the integrator
  std::int64_t smooth_steps = 0;            // steps of the smooth integration
  std::int64_t events = 0;                  // nonsmooth events
  std::int64_t impacts = 0;                 // events with an impact
  double wall_time = 0.0;                   // s
};

struct SimulationOptions {
  // Interactions may start with gaps down to -penetration_tolerance (m), round-off of
  // touching bodies; below that the model is rejected.
  double penetration_tolerance = 1e-9;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("penetration_tolerance", self.penetration_tolerance, at_least(0.0, "m"));
  }
};

// The problems of a simulation, which it hands its integrator: those, and only those, that
// the integrator needs (OneStepIntegrator::needs()).
struct SimulationProblems {
  std::unique_ptr<ImpactProblem> impacts;
  std::unique_ptr<ContactForceProblem> contact_forces;
};

// The generic loop: the integrator advances the system from one event to the next (time
// events for output from a queue, nonsmooth events it finds itself), observers are told.
class Simulation {
 public:
  // Throws InvalidInput when the system or the integrator is missing, or when the problems
  // are not those the integrator needs.
  Simulation(std::shared_ptr<NonSmoothDynamicalSystem> system,
             std::unique_ptr<OneStepIntegrator> integrator, SimulationProblems problems = {},
             SimulationOptions options = {});

  // These three throw mimpact::Error while the simulation runs (from an observer, or from
  // another thread), and InvalidInput for times that are not finite.
  void add_observer(SimulationObserver& observer);
  // Output times: on_output is called when the simulation reaches them.
  void schedule_output(double time);
  // start, start + interval, ... up to end: at most kMostOutputs of them.
  void schedule_outputs(double start, double interval, double end);
  static constexpr double kMostOutputs = 1e9;

  // Runs from the systems' current state at time `start` to `end`, or until an observer
  // terminates it. Throws InvalidInput for times that are not finite or in order and for a model
  // the problems cannot handle (a law, a mass, an initial interpenetration); mimpact::Error
  // while it is already running: one run at a time, whatever the thread.
  RunSummary run(double start, double end);
  // run() in three calls, as Drake's Simulator::Initialize and AdvanceTo, for a caller that
  // reads the state between times of its own: initialize at `start` (the checks of run, then
  // on_start), advance_to each time in turn (false once an observer has terminated the run;
  // InvalidInput for a time before time()), then finish (on_end and the summary). Each throws
  // mimpact::Error out of that order or while another call runs.
  void initialize(double start);
  bool advance_to(double end);
  RunSummary finish();
  bool running() const { return running_.load(); }

  double time() const { return time_; }
  const NonSmoothDynamicalSystem& system() const { return *system_; }
  const OneStepIntegrator& integrator() const { return *integrator_; }

 private:
  // the three stages of a run, with running_ held by the caller
  void start_at(double start);
  bool advance(double end);
  RunSummary end_run();

  template <class Call>
  void tell(Call&& call) {
    for (SimulationObserver* observer : observers_) call(*observer);
  }

  std::shared_ptr<NonSmoothDynamicalSystem> system_;
  std::unique_ptr<OneStepIntegrator> integrator_;
  SimulationProblems problems_;
  SimulationOptions options_;
  std::vector<SimulationObserver*> observers_;
  OutputTimes outputs_;
  double time_ = 0.0;
  std::atomic<bool> running_ = false;  // within a call of initialize, advance_to or finish
  bool initialized_ = false;           // from initialize to finish
  RunSummary summary_;
  std::optional<EventStatus> termination_;
  std::chrono::steady_clock::time_point clock_start_;
};

}  // namespace mimpact::kernel
