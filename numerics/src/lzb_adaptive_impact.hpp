#pragma once

// The integration of one adaptive LZB impact (adaptive_lzb::Impact, held by
// LzbAdaptiveIntegrator), defined in lzb_adaptive_integrator.cpp (segments, the right-hand side,
// the run) and lzb_adaptive_events.cpp (switches located as events); its state lives in
// lzb_adaptive_state.hpp, its within-steps strategy in lzb_adaptive_within_steps.hpp and its
// friction in lzb_adaptive_friction.hpp.
// docs/design/adaptive_lzb.md says how it integrates.

#include <cfloat>
#include <cmath>
#include <string>
#include <vector>

#include "lzb_adaptive_friction.hpp"
#include "lzb_adaptive_state.hpp"
#include "lzb_adaptive_within_steps.hpp"
#include "mimpact/numerics/dense_output.hpp"
#include "mimpact/numerics/event_scan.hpp"
#include "mimpact/numerics/impact_integrator.hpp"
#include "mimpact/numerics/impact_observer.hpp"
#include "mimpact/numerics/lzb_adaptive_options.hpp"

namespace mimpact::numerics::adaptive_lzb {

// Interior samples of each step searched for switches (besides its two ends). A velocity that
// crosses 0 and back between two samples, a third of a step apart, turns within the step's
// error: the switch it misses changes the result by about the tolerance.
constexpr int kSamplesPerStep = 2;

// The share of the tolerance allowed to each step's local error: the errors of a few hundred
// steps add up, and the velocities and the energy must come out within the tolerance
// (docs/design/adaptive_lzb.md, "The state and the tolerances").
constexpr double kLocalErrorShare = 1.0 / 100.0;

// The integration of one impact: segments between switches, each an ODE in its members'
// delta_j and P_j (lzb_adaptive_state.hpp), its switches located as events or, with the
// within-steps strategy, kept within the steps (lzb_adaptive_within_steps.hpp).
class Impact {
 public:
  explicit Impact(double tolerance)
      : ode_(kLocalErrorShare * tolerance, kLocalErrorShare * tolerance),
        within_(shared_, ode_),
        friction_(shared_, ode_) {}
  Impact(const Impact&) = delete;
  Impact& operator=(const Impact&) = delete;

  void run(const ImpactIntegrator::Input& input, const LzbAdaptiveOptions& options,
           ImpactSampler& sampler, ImpactObserver* observer, ImpactResult& result);

 private:
  using State = DenseOutput::State;

  void prepare(const ImpactIntegrator::Input& input, const LzbAdaptiveOptions& options);
  void begin_segment();
  void size_segment();
  // u of every member for the ODE state y (the increments of P applied through H's columns)
  void member_velocities(const State& y, std::vector<double>& velocity) const;
  void derivative(const State& y, State& dydt);
  void watch(double t, Watched& values);
  void locate(double t0, double t1, const Watched& before, const Watched& after,
              std::vector<Crossing>& found);
  double watched_value(std::size_t member, int kind, const Watched& values) const;
  // the same for one member at the state y: its velocity from its column of H alone
  double member_velocity(const State& y, std::size_t member) const;
  double member_value(std::size_t member, int kind, const State& y) const;
  void end_segment(const State& y);
  void account_work(const State& y);
  void apply(const std::vector<Crossing>& crossings, double t);
  bool settled(const State& y);
  void sample_until(double t, ImpactObserver& observer);
  void notify(double t, const State* y, ImpactObserver& observer);
  void finish(double t, ImpactResult& result);
  // why the impact stops before its end (its steps or its events spent), or empty
  std::string budget_spent(const LzbAdaptiveOptions& options, std::int64_t restarts,
                           std::int64_t most_events) const;
  // ends the impact where it is, with status step_limit and `message`
  void stop_at_budget(const std::string& message, ImpactObserver* observer, ImpactResult& result);

  ImpactState shared_;  // H, the contacts and the segment, shared with within_ and friction_
  DenseOutput ode_;
  WithinSteps within_;
  Friction friction_;
  double sample_interval_ = 0.0;
  std::int64_t steps_ = 0, contact_steps_ = 0;
  double segment_start_ = 0.0, last_sample_ = 0.0, closed_impulse_sum_ = 0.0;
  ImpactSampler* sampler_ = nullptr;  // the integrator's, for the impact being integrated
};

// u of every member (read by the right-hand side and the event search alike: inline in both)
inline void Impact::member_velocities(const State& y, std::vector<double>& velocity) const {
  for (std::size_t p = 0; p < shared_.segment.members.size(); ++p)
    velocity[p] = shared_.contact.velocity[shared_.segment.members[p]];
  const int* start = shared_.H->outerIndexPtr();
  const int* row = shared_.H->innerIndexPtr();
  const double* value = shared_.H->valuePtr();
  for (std::size_t a = 0; a < shared_.segment.active; ++a) {
    const Eigen::Index j = shared_.segment.members[a];
    const double increment = y[shared_.segment.active + a] * shared_.law.impulse_scale[j];
    // (a segment within the steps: its outer ring has neighbours beyond the members, moved by
    // end_segment)
    for (int k = start[j]; k < start[j + 1]; ++k)
      if (const int other = shared_.contact.member_of[row[k]]; other >= 0)
        velocity[std::size_t(other)] += value[k] * increment;
  }
  if (friction_.on()) friction_.push_normal(y, velocity);
}

// The quantity that is > 0 before the switch `kind` of a member and <= 0 once it happened (read
// for every member at both ends of every step: inline)
inline double Impact::watched_value(std::size_t member, int kind, const Watched& values) const {
  switch (kind) {
    case join:
      return values.velocity[member] + shared_.velocity_tolerance;
    case compression_end:
      return -values.velocity[member];
    case reload:
      return values.velocity[member];
    default:  // release
      return values.delta[member] - shared_.contact.release_level[shared_.segment.members[member]];
  }
}

}  // namespace mimpact::numerics::adaptive_lzb
