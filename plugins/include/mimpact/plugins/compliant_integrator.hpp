#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mimpact/kernel/one_step_integrator.hpp"
#include "mimpact/kernel/parameters.hpp"
#include "mimpact/numerics/contact_law.hpp"

namespace mimpact::plugins {

struct CompliantOptions {
  double absolute_tolerance = 1e-12;  // error control (q and v units)
  double relative_tolerance = 1e-10;
  double max_step = 0.0;              // s; 0 for no limit
  double event_tolerance = 1e-13;     // s: contacts open, close and turn at located times
  int samples_per_step = 4;           // interior samples searched for those events
  // The run is abandoned with an error past this many time steps: the largest run of
  // docs/performance.md takes 8.9e4, so 1e7 only stops runs whose scales double precision
  // cannot resolve.
  std::int64_t max_steps = 10'000'000;
  bool is_valid(std::string* why) const;
};

// The compliant model the LZB impulse dynamics reparametrizes, integrated in time: every
// interaction with an LzbLaw is a contact of force F = K delta^eta while it loads
// (delta = -g > 0 beyond its largest value so far, delta_M), and for e < 1 unloads and
// reloads along F = F_M ((delta - delta_r) / (delta_M - delta_r))^eta, delta_r = delta_M (1 - e^2),
// F_M = K delta_M^eta (LZB.md section 3); a contact that opens (delta <= 0) forgets its
// history. For e = 1 this is exactly the Hertz contact, the reference LZB converges to.
// M q'' = F_ext + W f(delta) is integrated by Dormand-Prince 5(4) with dense output; the
// times where a contact closes, opens or turns from loading to unloading are located (TOMS
// 748) and the integration restarts there, so the kinks of f are never stepped over. With
// linear relations the right-hand side works on W, constant and sparse, with no call per
// contact. It solves no impact problem: every contact is compliant. Registered as "compliant".
class CompliantIntegrator : public kernel::OneStepIntegrator {
 public:
  explicit CompliantIntegrator(CompliantOptions options = {});
  ~CompliantIntegrator() override;
  static std::unique_ptr<kernel::OneStepIntegrator> create(const kernel::Parameters& parameters);

  std::string_view name() const override { return "compliant"; }
  void initialize(kernel::NonSmoothDynamicalSystem& system, double start,
                  kernel::ImpactProblem& impacts, kernel::ContactForceProblem& forces) override;
  // Advances to `target`; reports an event (without impact) when a contact closes or opens.
  kernel::StepReport advance(double target) override;
  double time() const override { return time_; }

  // The contact forces at the current state (N), per interaction.
  const std::vector<double>& forces() const { return force_; }
  // Largest force of each contact so far and when (s), and its impulse (N s).
  const std::vector<double>& max_forces() const { return max_force_; }
  const std::vector<double>& times_of_max_force() const { return time_of_max_; }
  const std::vector<double>& impulses() const { return impulse_; }
  // Every contact open, and no two bodies approaching where a contact could close.
  bool contacts_open() const;

 private:
  struct State;
  void evaluate(double t, const double* y, double* dydt);
  // gaps (m) and normal velocities (m/s) of every contact at (q, v); works in state_'s buffers
  void gaps(const double* q, const double* v, std::vector<double>& gap, std::vector<double>& rate) const;
  double contact_force(std::size_t j, double delta) const;
  void restart();
  // the round-off of each gap at the start of a segment
  void estimate_gap_noise();
  // at the end of a segment: every contact's force and the largest so far; an open contact
  // loses its unloading history
  void account_segment_end();

  CompliantOptions options_;
  kernel::NonSmoothDynamicalSystem* system_ = nullptr;
  std::unique_ptr<State> state_;
  double time_ = 0.0;
  std::vector<numerics::ContactLaw> laws_;
  std::vector<double> max_compression_;  // delta_M per contact
  std::vector<double> force_, max_force_, time_of_max_, impulse_;
};

}  // namespace mimpact::plugins
