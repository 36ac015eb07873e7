#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mimpact/common/fields.hpp"
#include "mimpact/kernel/one_step_integrator.hpp"
#include "mimpact/numerics/contact_law.hpp"
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

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    numerics::OdeOptions::visit_fields(self.ode, field);
    field("max_steps", self.max_steps, at_least(1));
  }
};

// The compliant model the LZB impulse dynamics reparametrizes, integrated in time: every
// interaction with an LzbLaw is a contact of force F = K delta^eta while it loads
// (delta = -g > 0 beyond its largest value so far, delta_M), and for e < 1 unloads and
// reloads along F = F_M ((delta - delta_r) / (delta_M - delta_r))^eta, delta_r = delta_M (1 - e^2),
// F_M = K delta_M^eta (docs/model.md, section 3); a contact that opens (delta <= 0) forgets its
// history. For e = 1 this is exactly the Hertz contact, the reference LZB converges to.
// M q'' = F_ext + W f(delta) is integrated by Dormand-Prince 5(4) with dense output; the
// times where a contact closes, opens or turns from loading to unloading are located (TOMS
// 748) and the integration restarts there, so the kinks of f are never stepped over. With
// linear relations the right-hand side works on W, constant and sparse, with no call per
// contact. It solves no impact problem: every contact is compliant. Registered as "compliant".
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
  // Advances to `target`; reports an event (without impact) when a contact closes or opens.
  kernel::StepReport advance(double target) override;
  double time() const override { return time_; }
  // Every contact's force now, its largest so far and when, its impulse; all_open when
  // every contact is open and no two bodies approach where a contact could close.
  const kernel::ContactForceHistory* contact_force_history() const override { return &history_; }

 private:
  struct State;
  struct Event;
  // the phases of an advance
  void take_step();
  // the earliest contact event in [a, b] of the current step, if any
  bool next_event(double a, double b, Event& event);
  // moves to `end` in the current step: every contact's force and the largest so far
  void end_segment(double end);
  // updates the contact's history at its event; true when the event ends the advance
  bool handle_event(const Event& event, kernel::StepReport& report);
  void finish_advance();

  void evaluate(double t, const double* y, double* dydt);
  // gaps (m) and normal velocities (m/s) of every contact at (q, v); works in state_'s buffers
  void gaps(const double* q, const double* v, std::vector<double>& gap,
            std::vector<double>& rate) const;
  double contact_force(std::size_t j, double delta) const;
  void restart();
  // the round-off of each gap at the start of a segment
  void estimate_gap_noise();
  // every contact open, and none approaching
  bool contacts_open() const;

  CompliantOptions options_;
  kernel::NonSmoothDynamicalSystem* system_ = nullptr;
  std::unique_ptr<State> state_;
  double time_ = 0.0;
  std::vector<numerics::ContactLaw> laws_;
  std::vector<double> max_compression_;  // delta_M per contact
  kernel::ContactForceHistory history_;
};

}  // namespace mimpact::plugins
