#pragma once

#include <memory>
#include <string>
#include <vector>

#include "mimpact/common/fields.hpp"
#include "mimpact/kernel/one_step_integrator.hpp"
#include "mimpact/numerics/ode_options.hpp"

namespace mimpact::plugins {

using kernel::Index;
using kernel::VectorXd;

struct EventDrivenOptions {
  numerics::OdeOptions ode;          // the smooth motion and its event location
  double gap_tolerance = 1e-9;       // m: a contact with a gap up to this is closed
  double velocity_tolerance = 1e-9;  // m/s: a closed contact slower than this does not impact
  // Accumulation rule: a closed contact whose next flight (2 u / |g''|, u its separation
  // velocity, g'' the free acceleration of its gap) would last less than this comes to rest
  // (s). It ends the infinite bounce sequence of a dissipative contact under a steady load.
  double rest_flight_time = 1e-6;
  int max_events_at_one_instant = 10000;  // more means the events never end there: an error

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    numerics::OdeOptions::visit_fields(self.ode, field);
    field("gap_tolerance", self.gap_tolerance, at_least(0.0, "m"));
    field("velocity_tolerance", self.velocity_tolerance, at_least(0.0, "m/s"));
    field("rest_flight_time", self.rest_flight_time, at_least(0.0, "s"));
    field("max_events_at_one_instant", self.max_events_at_one_instant, at_least(1));
  }
};

// the smooth motion and what its event search watches (src/event_driven_motion.hpp)
struct EventDrivenMotion;
struct EventDrivenWatch;

// The event-driven scheme of Nguyen & Brogliato (2011) (section 2.2, algorithms 4-6). Between
// events the smooth motion M q'' = F + W_s lambda keeps the persistent contacts s closed
// (bilateral, lambda from H_s lambda = -b_s); it is integrated by the Dormand-Prince 5(4) method of
// Boost.Odeint with dense output, or exactly as q + v t when no force acts (no ODE then).
// Events are searched on the dense output at interior samples of every step: gaps of the
// other contacts closing (including a dip below 0 and back between two samples, found
// through the sign change of u), and forces of persistent contacts vanishing. They are
// placed with the TOMS 748 method to options.ode.event_tolerance; contacts closing within that
// tolerance of each other form one simultaneous impact, solved by the impact problem.
// Before the next smooth motion (Nguyen & Brogliato's algorithm 6): closed contacts leaving an
// impact with u about 0, or with a flight shorter than rest_flight_time, come to rest (their u set
// to 0 by the least-energy velocity change), and the acceleration-level problem decides which
// resting contacts stay closed. A held contact with friction (an LzbLaw's mu > 0, tangent rows)
// slides under Coulomb's law or sticks within its cone, its switches located as events too
// (SmoothFriction, src/smooth_friction.hpp). Registered as "event-driven".
class EventDrivenIntegrator : public kernel::OneStepIntegrator {
 public:
  using Options = EventDrivenOptions;
  // Throws InvalidInput naming an option out of range.
  explicit EventDrivenIntegrator(EventDrivenOptions options = {});
  ~EventDrivenIntegrator() override;

  std::string_view name() const override { return "event-driven"; }
  // An impact problem for the impacts, a contact force problem for the resting contacts.
  Needs needs() const override { return {.impacts = true, .contact_forces = true}; }
  void initialize(kernel::NonSmoothDynamicalSystem& system, double start,
                  const kernel::EventProblems& problems) override;
  kernel::StepReport advance(double target) override;
  double time() const override { return time_; }

  // True while the smooth motion needs a differential equation (some force acts, or a
  // persistent contact with a nonlinear relation); false while it is the exact q + v t.
  bool integrates_ode() const { return !free_flight_; }
  // Forces of the persistent contacts holding them closed at the current state.
  kernel::ContactForces persistent_forces();
  const EventDrivenOptions& options() const { return options_; }

 private:
  using Motion = EventDrivenMotion;
  using Watched = EventDrivenWatch;
  struct Event {
    double time;
    std::vector<Index> closing, detaching;
    std::vector<Index> switches;  // of the Coulomb phases' watched values (SmoothFriction)
  };

  // the phases of algorithm 6, before the next smooth motion
  void settle(kernel::StepReport& report);
  void restore_penetrations();
  std::vector<Index> bring_to_rest();
  void hold_resting(const std::vector<Index>& resting, kernel::StepReport& report);

  void process_event(const Event& event, kernel::StepReport& report);
  // the time up to which the motion is known past time_: integrates the ODE as needed
  double known_until(kernel::StepReport& report);
  void derivative(const std::vector<double>& y, std::vector<double>& dydt, double t);
  // earliest event in [a, b] of the current motion, if any
  bool search(double a, double b, Event& event);
  void move_to(double t);
  void state_at(double t, VectorXd& q, VectorXd& v);
  void watch(double t, Watched& values);
  double gap_function(Index j, double t);
  double rate_function(Index j, double t);
  double force_function(Index k, double t);
  double friction_function(Index value, double t);
  void switch_phases(const Event& event);
  // when contact j closes between the samples t0 and t1, or infinity; `level` is the gap at
  // which it counts as closing
  double closing_time(Index j, double t0, double t1, const Watched& before, const Watched& after,
                      double& level);
  void restart_motion();
  void check_event_loop(double t);

  EventDrivenOptions options_;
  kernel::NonSmoothDynamicalSystem* system_ = nullptr;
  kernel::ImpactProblem* impacts_ = nullptr;
  kernel::ContactForceProblem* forces_ = nullptr;
  std::unique_ptr<Motion> motion_;
  double time_ = 0.0;
  VectorXd q_, v_;                // the state at time_
  bool free_flight_ = true;       // the motion is q + v t
  bool impact_pending_ = false;   // closed contacts approach at time_
  bool settle_pending_ = false;   // algorithm 6 still to finish at time_
  std::vector<Index> closed_;     // I_c at the last event
  VectorXd velocity_resolution_;  // per interaction, from the last impact
  double last_event_time_ = -1.0;
  int events_at_instant_ = 0;
};

}  // namespace mimpact::plugins
