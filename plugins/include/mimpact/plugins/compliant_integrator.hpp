#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "mimpact/common/fields.hpp"
#include "mimpact/kernel/one_step_integrator.hpp"
#include "mimpact/numerics/contact_law.hpp"
#include "mimpact/numerics/event_scan.hpp"
#include "mimpact/numerics/mindlin_spring.hpp"
#include "mimpact/numerics/ode_options.hpp"

namespace mimpact::plugins {

struct CompliantOptions {
  // the smooth integration: error control, and the times where contacts open, close and turn
  numerics::OdeOptions ode{.absolute_tolerance = 1e-12,
                           .relative_tolerance = 1e-10,
                           .event_tolerance = 1e-13,
                           .samples_per_step = 4};
  // The run is abandoned with an error past this many time steps: the largest run of
  // docs/performance.md takes 8.9e4, so 1e7 only stops runs whose scales double precision
  // cannot resolve.
  std::int64_t max_steps = 10'000'000;
  // m: a contact joins the integration when its overlap exceeds this, and leaves it below half
  // of it. Smaller overlaps carry forces of K resolution^eta and no more; 1e-6 of the
  // impact's largest overlap is below 1e-9 of its peak force and 1e-15 of its energy.
  double overlap_resolution = 1e-12;
  // Linear relations: a contact that opens forgets its gap where it stops separating, and
  // closes again from there (g = 0). This is the LZB impact's frozen configuration, under which
  // no gap opens (docs/model.md, section 13): the compliant contacts are then the continuous
  // limit of LZB for e = 1 even where contacts open and close again within the impact. Off, the
  // bodies must close the gaps they opened, as real beads do.
  bool frozen_gaps = false;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    numerics::OdeOptions::visit_fields(self.ode, field);
    field("max_steps", self.max_steps, at_least(1));
    field("overlap_resolution", self.overlap_resolution, positive("m"));
    field("frozen_gaps", self.frozen_gaps);
  }
};

// The compliant model the LZB impulse dynamics reparametrizes, integrated in time: every
// interaction with an LzbLaw is a contact of force F = K delta^eta while it loads
// (delta = -g > 0 beyond its largest value so far, delta_M), and for e < 1 unloads and
// reloads along F = F_M ((delta - delta_r) / (delta_M - delta_r))^eta, delta_r = delta_M (1 - e^2),
// F_M = K delta_M^eta (docs/model.md, section 3); a contact that opens forgets its history.
// For e = 1 this is exactly the Hertz contact, the reference LZB converges to.
// M q'' = F_ext + W f(delta) is integrated by Dormand-Prince 5(4) with dense output; the
// times where a contact joins, leaves or turns from loading to unloading are located (TOMS
// 748) and the integration restarts there, so the kinks of f are never stepped over.
//
// The work follows the contacts taking part (docs/design/compliant_contacts.md). With linear
// relations, a body with no force and a constant mass that touches no loaded contact moves in
// closed form, q + v t, and costs nothing; only the bodies of the loaded contacts are integrated,
// as displacements from where the last event left them (so a gap is a difference of small numbers
// however far the bodies lie from the origin). A contact joins the integration when its overlap
// reaches overlap_resolution and leaves it when the overlap falls below half of that; between two
// bodies in free flight its join time is computed, not searched. A contact that closes slower than
// ode.relative_tolerance times the fastest initial speed (behind a wave, beads at rest approaching
// at the integration's own error speeds) collides instantly, u+ = -e u-, instead of joining: its
// overlap lies below what the error control resolves, and integrating it only fed those errors and
// kept ever more bodies in motion. With a nonlinear relation every body and contact is integrated.
// A contact with friction (its law's mu > 0, its linear relation's tangent rows) follows
// Coulomb's law with a rigid tangential response, or with its law's tangential stiffness ratio
// > 0 through a Mindlin spring (compliant_friction.cpp; docs/friction.md, sections 2 and 3), and
// is always integrated, never collided instantly.
// It solves no impact problem: every contact is compliant. Registered as "compliant".
namespace compliant {
struct State;  // the integration's state and its bodies and contacts (src/compliant_state.hpp)
struct Event;
}  // namespace compliant

class CompliantIntegrator : public kernel::OneStepIntegrator {
 public:
  using Options = CompliantOptions;
  // Throws InvalidInput naming an option out of range.
  explicit CompliantIntegrator(CompliantOptions options = {});
  ~CompliantIntegrator() override;

  std::string_view name() const override { return "compliant"; }
  // Every contact is compliant: no impact or contact force problem.
  Needs needs() const override { return {}; }
  void initialize(kernel::NonSmoothDynamicalSystem& system, double start,
                  const kernel::EventProblems& problems) override;
  // Advances to `target`; reports an event (without impact) when a contact joins (closing)
  // or leaves (detaching). At such an event the integrated bodies are written back to the
  // system; the bodies in free flight are written back when the advance reaches its target.
  kernel::StepReport advance(double target) override;
  double time() const override { return time_; }
  // Every contact's force now, its largest so far and when, its impulse; all_open when
  // every contact is open and no two bodies approach where a contact could close.
  const kernel::ContactForceHistory* contact_force_history() const override { return &history_; }
  // Bodies integrated now, and the most integrated at once since initialize().
  kernel::Index bodies_in_motion() const;
  kernel::Index most_bodies_in_motion() const;

 private:
  using State = compliant::State;
  using Event = compliant::Event;
  // the phases of an advance
  void take_step();
  // the earliest contact event in [a, b] of the current step, if any
  bool next_event(double a, double b, Event& event);
  // gaps (m) and rates (m/s) of `contacts` at time t of the current step
  void measure(double t, std::span<const kernel::Index> contacts, std::vector<double>& gap,
               std::vector<double>& rate);
  // the earliest join computed between bodies in free flight in [a, b], if any
  bool next_predicted_join(double a, double b, Event& event);
  // moves to `end` in the current step: the joined contacts' forces and largest forces
  void end_segment(double end);
  // applies the event; true when it ends the advance
  bool handle_event(const Event& event, kernel::StepReport& report);
  void finish_advance(bool reached_target);
  // the body's state now into the system
  void write_back(kernel::Index body);

  // who takes part (compliant_motion.cpp): the integrated state folded into the bodies' anchors,
  // bodies set in motion or in free flight, contacts that join and leave
  void commit_motion();
  void set_in_motion(kernel::Index body);
  void fold_flight(kernel::Index body);
  void set_free(kernel::Index body);
  void join(kernel::Index contact);
  void leave(kernel::Index contact);
  void predict_join(kernel::Index contact);
  void forget_prediction(kernel::Index contact);
  // the integration restarted on the moving set (compliant_integrator.cpp)
  void restart();

  void evaluate(double t, const double* y, double* dydt);
  // the laws and the ledger (compliant_ledger.cpp)
  double contact_force(std::size_t j, double delta) const;
  // the potential energy of contact j at overlap delta (J), on its loading or unloading curve
  double contact_energy(std::size_t j, double delta) const;
  // the contacts' work and the forces' since the last accounting point, with the state y at t
  void account_work(double t);
  void start_accounting();
  // a closing contact slower than slow_speed_ collides instantly instead of joining
  bool collide_instantly(kernel::Index contact);
  void update_stored_energy();
  // every contact open, and none approaching
  bool contacts_open();

  // Coulomb's law on the contacts that rub (compliant_friction.cpp): each contact's tangent rows
  // and mu; at a restart, the rubbing contacts' impulses appended to y and their phases chosen;
  // the forces of the slipping rows and springs (onto the generalized force, before M^-1, with
  // the springs' stretch rates) and of the sticking rows (onto the accelerations, after it) with
  // every row's dP_t/dt; the switches watched and located along the step, and passed (before
  // the commit); the impulses and stretches committed; the tangential forces' work accounted at t
  void prepare_friction();
  void restart_friction();
  void add_tangential_forces(double t, const double* y, double* dydt);
  void tangential_rates(double* dydt);
  void factor_stick();
  void watch_friction(double t, std::vector<double>& values);
  void locate_switches(double t0, double t1, const std::vector<double>& before,
                       const std::vector<double>& after, std::vector<numerics::Crossing>& found);
  void pass_switch(const Event& event);
  // the spring of contact j at time t with the integrated state y
  numerics::mindlin::Terms spring_terms(kernel::Index j, double t, const double* y) const;
  // the watched value whose crossing a Crossing's kind says (locate_switches), -1 for a contact's
  static int coulomb_switch(int kind);
  void commit_friction();
  void account_slip();

  CompliantOptions options_;
  kernel::NonSmoothDynamicalSystem* system_ = nullptr;
  std::unique_ptr<State> state_;
  double time_ = 0.0;
  std::vector<numerics::ContactLaw> laws_;
  std::vector<double> max_compression_;  // delta_M per contact
  // m/s: relative tolerance x the fastest initial speed; slower collisions are not integrated
  double slow_speed_ = 0.0;
  kernel::ContactForceHistory history_;
};

}  // namespace mimpact::plugins
