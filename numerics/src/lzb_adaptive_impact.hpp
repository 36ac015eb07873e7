#pragma once

// The state of one adaptive LZB impact (adaptive_lzb::Impact, held by LzbAdaptiveIntegrator),
// shared by its sources: lzb_adaptive_integrator.cpp (segments, the right-hand side, the run),
// lzb_adaptive_events.cpp (switches located as events) and lzb_adaptive_within_steps.cpp (switches
// kept within the steps). docs/design/adaptive_lzb.md says how it integrates.

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "mimpact/numerics/dense_output.hpp"
#include "mimpact/numerics/event_scan.hpp"
#include "mimpact/numerics/impact_integrator.hpp"
#include "mimpact/numerics/impact_observer.hpp"
#include "mimpact/numerics/lzb_adaptive_options.hpp"

namespace mimpact::numerics::adaptive_lzb {

// Where a contact is in its cycle (docs/model.md, section 10).
enum class Phase : unsigned char { open, compression, expansion };

// The switches of the right-hand side, each located as an event.
enum EventKind : int {
  join = 0,         // an open contact starts approaching: it enters compression at delta = 0
  compression_end,  // u_j reaches 0 from below: delta_j is at its largest, expansion begins
  reload,           // u_j of an expanding contact turns negative: compression again
  release,          // delta_j reaches its release level: the contact leaves the impact
};

// Interior samples of each step searched for switches (besides its two ends). A velocity that
// crosses 0 and back between two samples, a third of a step apart, turns within the step's
// error: the switch it misses changes the result by about the tolerance.
constexpr int kSamplesPerStep = 2;

// The share of the tolerance allowed to each step's local error: the errors of a few hundred
// steps add up, and the velocities and the energy must come out within the tolerance (with
// share 1/30 a lone elastic contact at 1e-9 gained 1.3 times it; with 1/100 the extremes
// suite's largest is 0.93 times it, at 1e-12).
constexpr double kLocalErrorShare = 1.0 / 100.0;

// Where a member's u_j changed sign within a step kept whole.
struct Turn {
  std::size_t member;
  double time;
  bool closing;  // u_j turned negative (else positive: a peak of delta_j)
};

// The watched quantities at one time: the members' velocities and the active ones' delta.
struct Watched {
  std::vector<double> velocity, delta;
};

// The state of one impact. Contacts are members of the current segment (between two
// switches) when they hold energy (active: their delta_j and the increment of P_j since the
// segment began are the ODE's state, scaled to order one) or when an active one pushes them
// (watched: open, their velocity followed to catch them joining). The other contacts do not
// change and cost nothing.
class Impact {
 public:
  explicit Impact(double tolerance)
      : ode_(kLocalErrorShare * tolerance, kLocalErrorShare * tolerance) {}

  void run(const ImpactIntegrator::Input& input, const LzbAdaptiveOptions& options,
           ImpactSampler& sampler, ImpactObserver* observer, ImpactResult& result);

 private:
  using State = DenseOutput::State;

  void prepare(const Eigen::VectorXd& diagonal, const Eigen::VectorXd& u_minus,
               const LawTable& laws, const LzbAdaptiveOptions& options);
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
  // u_j of one member from its column of H alone (H is symmetric: column j holds row j, the
  // contacts whose impulses move u_j); `impulse(a)` gives active member a's scaled P increment
  template <class Impulse>
  double column_velocity(std::size_t member, Impulse&& impulse) const {
    const Eigen::Index j = segment_.members[member];
    double velocity = contact_.velocity[j];
    const int* start = H_->outerIndexPtr();
    const int* row = H_->innerIndexPtr();
    const double* value = H_->valuePtr();
    for (int k = start[j]; k < start[j + 1]; ++k) {
      const int other = contact_.member_of[row[k]];
      if (other >= 0 && std::size_t(other) < segment_.active)
        velocity += value[k] * impulse(std::size_t(other)) * law_.impulse_scale[row[k]];
    }
    return velocity;
  }
  void end_segment(const State& y);
  void account_work(const State& y);
  void apply(const std::vector<Crossing>& crossings, double t);
  bool settled(const State& y);
  void sample_until(double t, ImpactObserver& observer);
  void notify(double t, const State* y, ImpactObserver& observer);
  void finish(double t, ImpactResult& result);

  // An impact whose every law is continuous at the switches (e = 1, or bi-stiffness with e > 0:
  // d delta_j/dt = -u_j or -u_j / e^2 meet where u_j = 0) keeps them within the steps
  // (docs/design/adaptive_lzb.md): its members, the contacts holding energy or approaching and two
  // rings of their neighbours, all carry delta_j and P_j; a contact's delta_j runs below 0 once
  // it separates, its force K max(delta_j, 0)^eta switching off by itself, and where it
  // approaches again (u_j turning negative, a "closing" turn) it is set back to the clamp,
  // delta_j - delta_j(turn); where an inelastic contact's u_j changes sign, delta_j goes on at
  // the other rate. Both are settled after the step: the contact integrated again alone from
  // the turn.
  void begin_within_steps_segment();
  void locate_turns(double t0, double t1, const Watched& before, const Watched& after);
  double member_velocity_at(const DenseOutput::Weights& w, std::size_t member) const;
  // the peaks and closings of the step [t0, t1] just taken; true if one changed the state (then
  // within_.y_settled holds it)
  bool settle_turns(double t0, double t1);
  bool settle_member(double t0, double t1, std::span<const Turn> turns);
  // a contact of the outer ring holds energy or approaches: its neighbours must join
  bool outgrown(const State& y) const;

  // contact j holds energy or approaches faster than tolerance * V (at the last segment's end)
  bool takes_part(Eigen::Index j) const {
    return contact_.delta[j] > 0.0 || contact_.velocity[j] < -velocity_tolerance_;
  }
  double delta_of(std::size_t member, const State& y) const {
    return std::max(y[member], 0.0) * law_.delta_scale[segment_.members[member]];
  }
  double force(Eigen::Index j, double delta) const {
    return law_.stiffness[j] * power_law(delta, law_.exponent[j]);
  }
  double energy(Eigen::Index j, double delta) const {
    return force(j, delta) * delta / (1.0 + law_.exponent[j]);
  }

  // per contact: the law's constants and scales, fixed for the impact
  struct ContactConstants {
    std::vector<double> stiffness, exponent, expansion_rate, release_factor;
    std::vector<double> delta_scale, impulse_scale, energy_tolerance;
    std::vector<double> self_mobility;     // H_jj (1/kg)
    std::vector<bool> gives_nothing_back;  // e = 0

    void reset(std::size_t m) {
      for (auto* values : {&stiffness, &exponent, &expansion_rate, &release_factor, &delta_scale,
                           &impulse_scale, &energy_tolerance, &self_mobility})
        values->assign(m, 0.0);
      gives_nothing_back.assign(m, false);
    }
  };
  // per contact: the state at the start of the current segment
  struct ContactStates {
    std::vector<Phase> phase;
    std::vector<double> delta, impulse, velocity, release_level, max_force, time_of_max;
    std::vector<double> work;    // J, the integral of -u_j dP_j so far
    std::vector<int> member_of;  // the contact's place in the segment's members, -1 if none

    // open, unloaded, at u- (one entry per contact)
    void reset(const Eigen::VectorXd& u_minus) {
      const auto m = std::size_t(u_minus.size());
      phase.assign(m, Phase::open);
      for (auto* values : {&delta, &impulse, &release_level, &max_force, &time_of_max, &work})
        values->assign(m, 0.0);
      member_of.assign(m, -1);
      velocity.assign(u_minus.data(), u_minus.data() + m);
    }
  };
  // the current segment
  struct Segment {
    std::vector<Eigen::Index> members;  // the active contacts first, then the watched ones
    std::size_t active = 0;
    // per active member: d delta_j/dt = -rate u_j over the segment (1, or 1/e^2 expanding)
    std::vector<double> rate;
    State y, y_at;
    std::vector<double> rhs_velocity, velocity_at;
    // per active member: its impulse increment and velocity where the work was last accounted
    std::vector<double> accounted_impulse, accounted_velocity;
    Watched before, after;
    std::vector<Eigen::Index> previous_members;  // begin_segment's buffer
  };
  // within the steps (impacts whose laws are continuous at their switches)
  struct WithinSteps {
    bool continuous_laws = false;       // every contact's law continuous at its switches
    bool on = false;                    // the current segment keeps its switches within its steps
    std::size_t enter = 0, leave = 0;   // contacts taking part
    std::vector<unsigned char> ring;    // per member: 0 holding energy or approaching, 1, 2 around
    std::vector<Turn> turns;            // by member, then time, once settle_turns sorts them
    State y_settled;                    // the state at a step's end with its turns settled
    std::vector<Eigen::Index> pending;  // non-members a member's impulse set approaching
  };

  const Eigen::SparseMatrix<double>* H_ = nullptr;
  DenseOutput ode_;
  double velocity_tolerance_ = 0.0;  // tolerance * V (m/s)
  double sample_interval_ = 0.0;
  std::int64_t steps_ = 0, contact_steps_ = 0;
  double segment_start_ = 0.0, last_sample_ = 0.0, closed_impulse_sum_ = 0.0;
  double local_tolerance_ = 0.0;  // a step's error share, in the state's scaled units
  ContactConstants law_;
  ContactStates contact_;
  Segment segment_;
  WithinSteps within_;
  ImpactSampler* sampler_ = nullptr;  // the integrator's, for the impact being integrated
};

// u of every member (read by the right-hand side and the event search alike: inline in both)
inline void Impact::member_velocities(const State& y, std::vector<double>& velocity) const {
  for (std::size_t p = 0; p < segment_.members.size(); ++p)
    velocity[p] = contact_.velocity[segment_.members[p]];
  const int* start = H_->outerIndexPtr();
  const int* row = H_->innerIndexPtr();
  const double* value = H_->valuePtr();
  for (std::size_t a = 0; a < segment_.active; ++a) {
    const Eigen::Index j = segment_.members[a];
    const double increment = y[segment_.active + a] * law_.impulse_scale[j];
    // (a segment within the steps: its outer ring has neighbours beyond the members, moved by
    // end_segment)
    for (int k = start[j]; k < start[j + 1]; ++k)
      if (const int other = contact_.member_of[row[k]]; other >= 0)
        velocity[std::size_t(other)] += value[k] * increment;
  }
}

// The quantity that is > 0 before the switch `kind` of a member and <= 0 once it happened (read
// for every member at both ends of every step: inline)
inline double Impact::watched_value(std::size_t member, int kind, const Watched& values) const {
  switch (kind) {
    case join:
      return values.velocity[member] + velocity_tolerance_;
    case compression_end:
      return -values.velocity[member];
    case reload:
      return values.velocity[member];
    default:  // release
      return values.delta[member] - contact_.release_level[segment_.members[member]];
  }
}

}  // namespace mimpact::numerics::adaptive_lzb
