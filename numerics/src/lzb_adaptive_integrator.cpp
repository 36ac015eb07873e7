#include "mimpact/numerics/lzb_adaptive_integrator.hpp"

#include <algorithm>
#include <array>
#include <boost/numeric/odeint.hpp>
#include <cfloat>
#include <cmath>
#include <span>
#include <string>

#include "mimpact/common/error.hpp"
#include "mimpact/numerics/dense_output.hpp"
#include "mimpact/numerics/event_scan.hpp"
#include "mimpact/numerics/root_bracketing.hpp"

namespace mimpact::numerics {

using Eigen::Index;

namespace {

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

}  // namespace

// The state of one impact. Contacts are members of the current segment (between two
// switches) when they hold energy (active: their delta_j and the increment of P_j since the
// segment began are the ODE's state, scaled to order one) or when an active one pushes them
// (watched: open, their velocity followed to catch them joining). The other contacts do not
// change and cost nothing.
class LzbAdaptiveIntegrator::Impact {
 public:
  explicit Impact(double tolerance)
      : ode_(kLocalErrorShare * tolerance, kLocalErrorShare * tolerance) {}

  void run(const Eigen::SparseMatrix<double>& H, const Eigen::VectorXd& diagonal,
           const Eigen::VectorXd& u_minus, const LawTable& laws, const LzbAdaptiveOptions& options,
           ImpactSampler& sampler, ImpactObserver* observer, LzbResult& result);

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
    const Index j = members_[member];
    double velocity = velocity_[j];
    const int* start = H_->outerIndexPtr();
    const int* row = H_->innerIndexPtr();
    const double* value = H_->valuePtr();
    for (int k = start[j]; k < start[j + 1]; ++k) {
      const int other = member_of_[row[k]];
      if (other >= 0 && std::size_t(other) < active_)
        velocity += value[k] * impulse(std::size_t(other)) * impulse_scale_[row[k]];
    }
    return velocity;
  }
  void end_segment(const State& y);
  void account_work(const State& y);
  void apply(const std::vector<Crossing>& crossings, double t);
  bool settled(const State& y);
  void sample_until(double t, ImpactObserver& observer);
  void notify(double t, const State* y, ImpactObserver& observer);
  void finish(double t, LzbResult& result);

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
  // y_settled_ holds it)
  bool settle_turns(double t0, double t1);
  bool settle_member(double t0, double t1, std::span<const Turn> turns);
  // a contact of the outer ring holds energy or approaches: its neighbours must join
  bool outgrown(const State& y) const;

  // contact j holds energy or approaches faster than tolerance * V (at the last segment's end)
  bool takes_part(Index j) const { return delta_[j] > 0.0 || velocity_[j] < -velocity_tolerance_; }
  double delta_of(std::size_t member, const State& y) const {
    return std::max(y[member], 0.0) * delta_scale_[members_[member]];
  }
  double force(Index j, double delta) const {
    return stiffness_[j] * power_law(delta, exponent_[j]);
  }
  double energy(Index j, double delta) const {
    return force(j, delta) * delta / (1.0 + exponent_[j]);
  }

  const Eigen::SparseMatrix<double>* H_ = nullptr;
  DenseOutput ode_;
  double velocity_tolerance_ = 0.0;  // tolerance * V (m/s)
  double sample_interval_ = 0.0;
  std::int64_t steps_ = 0, contact_steps_ = 0;
  double segment_start_ = 0.0, last_sample_ = 0.0, closed_impulse_sum_ = 0.0;

  // per active member: d delta_j/dt = -rate u_j over the segment (1, or 1/e^2 expanding)
  std::vector<double> rate_;
  // per contact: law constants and scales
  std::vector<double> stiffness_, exponent_, expansion_rate_, release_factor_;
  std::vector<double> delta_scale_, impulse_scale_, energy_tolerance_;
  std::vector<double> self_mobility_;     // H_jj (1/kg)
  double local_tolerance_ = 0.0;          // a step's error share, in the state's scaled units
  std::vector<bool> gives_nothing_back_;  // e = 0
  // per contact: state at the start of the current segment
  std::vector<Phase> phase_;
  std::vector<double> delta_, impulse_, velocity_, release_level_, max_force_, time_of_max_;
  std::vector<double> work_;    // J, the integral of -u_j dP_j so far
  std::vector<int> member_of_;  // the contact's place in members_, -1 if none
  // the segment
  std::vector<Index> members_;  // the active contacts first, then the watched ones
  std::size_t active_ = 0;
  State y_, y_at_;
  std::vector<double> rhs_velocity_, velocity_at_;
  // per active member: its impulse increment and velocity where the work was last accounted
  std::vector<double> accounted_impulse_, accounted_velocity_;
  Watched before_, after_;
  std::vector<Index> previous_members_;  // begin_segment's buffer
  // within the steps (impacts whose laws are continuous at their switches)
  bool continuous_laws_ = false;  // every contact's law continuous at its switches
  bool within_steps_ = false;     // the current segment keeps its switches within its steps
  std::size_t enter_within_steps_ = 0, leave_within_steps_ = 0;  // contacts taking part
  std::vector<unsigned char> ring_;   // per member: 0 holding energy or approaching, 1, 2 around
  std::vector<Turn> turns_;           // by member, then time, once settle_turns sorts them
  State y_settled_;                   // the state at a step's end with its turns settled
  std::vector<Index> pending_;        // non-members a member's impulse set approaching
  ImpactSampler* sampler_ = nullptr;  // the integrator's, for the impact being integrated
};

void LzbAdaptiveIntegrator::Impact::prepare(const Eigen::VectorXd& diagonal,
                                            const Eigen::VectorXd& u_minus, const LawTable& laws,
                                            const LzbAdaptiveOptions& options) {
  const std::size_t m = laws.size();
  const double fastest = -u_minus.minCoeff();
  velocity_tolerance_ = options.tolerance * fastest;
  sample_interval_ = options.sample_interval;
  auto reset = [m](auto& buffer, auto value) { buffer.assign(m, value); };
  reset(stiffness_, 0.0);
  reset(exponent_, 0.0);
  reset(expansion_rate_, 0.0);
  reset(release_factor_, 0.0);
  reset(delta_scale_, 0.0);
  reset(impulse_scale_, 0.0);
  reset(energy_tolerance_, 0.0);
  reset(self_mobility_, 0.0);
  local_tolerance_ = kLocalErrorShare * options.tolerance;
  reset(gives_nothing_back_, false);
  for (std::size_t j = 0; j < m; ++j) {
    const LawConstants& law = laws[j];
    const double e2 = law.restitution * law.restitution;
    const bool mono = law.mono_stiffness;
    stiffness_[j] = law.stiffness;
    exponent_[j] = law.exponent;
    // expansion: d delta/dt = -u / e^2 (bi-stiffness) or -u (mono-stiffness)
    expansion_rate_[j] = mono || e2 == 0.0 ? 1.0 : law.inverse_e2;
    // released at delta_c (1 - e^2)^(1/(1+eta)) (mono-stiffness) or at 0 (bi-stiffness)
    release_factor_[j] = mono ? std::pow(1.0 - e2, 1.0 / law.one_plus_exponent) : 0.0;
    gives_nothing_back_[j] = law.restitution == 0.0;
    // the natural scales of contact j: the impulse that stops V, the indentation that stores
    // the energy V^2 / (2 H_jj)
    const double h = diagonal(Index(j));
    self_mobility_[j] = h;
    impulse_scale_[j] = fastest / h;
    delta_scale_[j] = std::pow((1.0 + law.exponent) * fastest * fastest / (2.0 * h * law.stiffness),
                               1.0 / (1.0 + law.exponent));
    energy_tolerance_[j] = velocity_tolerance_ * velocity_tolerance_ / (2.0 * h);
  }
  reset(phase_, Phase::open);
  reset(delta_, 0.0);
  reset(impulse_, 0.0);
  reset(release_level_, 0.0);
  reset(max_force_, 0.0);
  reset(time_of_max_, 0.0);
  reset(work_, 0.0);
  reset(member_of_, -1);
  velocity_.assign(u_minus.data(), u_minus.data() + m);
  for (std::size_t j = 0; j < m; ++j)
    if (velocity_[j] < -velocity_tolerance_) phase_[j] = Phase::compression;
  members_.clear();
  pending_.clear();
  continuous_laws_ = m > 0;
  for (std::size_t j = 0; j < m; ++j)
    continuous_laws_ = continuous_laws_ && (laws[j].restitution == 1.0 ||
                                            (!laws[j].mono_stiffness && laws[j].restitution > 0.0));
  within_steps_ = false;
  enter_within_steps_ = std::size_t(options.within_steps_from);
  leave_within_steps_ = enter_within_steps_ / 2;
  steps_ = contact_steps_ = 0;
  segment_start_ = last_sample_ = closed_impulse_sum_ = 0.0;
}

// The members of the segment that starts now: the contacts holding energy, then the open
// contacts their forces reach through H. The ODE state starts at [delta / scale, 0].
void LzbAdaptiveIntegrator::Impact::begin_segment() {
  if (continuous_laws_) {
    std::size_t core = 0;
    auto count = [&](Index j) { core += takes_part(j); };
    if (members_.empty())
      for (Index j = 0; j < Index(phase_.size()); ++j) count(j);
    for (Index j : members_) count(j);
    core += pending_.size();
    within_steps_ = core >= (within_steps_ ? leave_within_steps_ : enter_within_steps_);
  }
  if (within_steps_) {
    begin_within_steps_segment();
    return;
  }
  for (Index j : members_) member_of_[j] = -1;
  std::vector<Index>& previous = previous_members_;
  previous.swap(members_);
  members_.clear();
  previous.insert(previous.end(), pending_.begin(), pending_.end());
  pending_.clear();
  // the active contacts were members already (a contact becomes active only by a switch at a
  // member), so the new active set is found among the previous members, in their order
  for (Index j : previous)
    if (phase_[j] != Phase::open) {
      member_of_[j] = int(members_.size());
      members_.push_back(j);
    }
  if (previous.empty())  // the first segment
    for (Index j = 0; j < Index(phase_.size()); ++j)
      if (phase_[j] != Phase::open) {
        member_of_[j] = int(members_.size());
        members_.push_back(j);
      }
  active_ = members_.size();
  const int* start = H_->outerIndexPtr();
  const int* row = H_->innerIndexPtr();
  for (std::size_t a = 0; a < active_; ++a)
    for (int k = start[members_[a]]; k < start[members_[a] + 1]; ++k)
      if (member_of_[row[k]] < 0) {
        member_of_[row[k]] = int(members_.size());
        members_.push_back(row[k]);
      }
  size_segment();
}

// The members of a segment within the steps: the contacts holding energy or approaching faster than
// tolerance * V, then the ring of their neighbours through H, then the ring of those: a
// contact of the first ring may load within a step, and its impulse then moves only members.
void LzbAdaptiveIntegrator::Impact::begin_within_steps_segment() {
  for (Index j : members_) member_of_[j] = -1;
  std::vector<Index>& previous = previous_members_;
  previous.swap(members_);
  members_.clear();
  ring_.clear();
  auto take = [&](Index j, unsigned char ring) {
    member_of_[j] = int(members_.size());
    members_.push_back(j);
    ring_.push_back(ring);
  };
  auto core = [&](Index j) { return member_of_[j] < 0 && takes_part(j); };
  if (previous.empty() && pending_.empty()) {  // the first segment
    for (Index j = 0; j < Index(phase_.size()); ++j)
      if (core(j)) take(j, 0);
  }
  for (Index j : previous)
    if (core(j)) take(j, 0);
  for (Index j : pending_)
    if (core(j)) take(j, 0);
  pending_.clear();
  const int* start = H_->outerIndexPtr();
  const int* row = H_->innerIndexPtr();
  std::size_t ring_start = 0;
  for (unsigned char ring = 1; ring <= 2; ++ring) {
    const std::size_t ring_end = members_.size();
    for (std::size_t a = ring_start; a < ring_end; ++a)
      for (int k = start[members_[a]]; k < start[members_[a] + 1]; ++k)
        if (member_of_[row[k]] < 0) take(row[k], ring);
    ring_start = ring_end;
  }
  active_ = members_.size();
  size_segment();
}

// The ODE state [delta / scale, 0] of the members that carry one, and the buffers.
void LzbAdaptiveIntegrator::Impact::size_segment() {
  y_.assign(2 * active_, 0.0);
  y_at_.assign(2 * active_, 0.0);
  rate_.resize(active_);
  for (std::size_t a = 0; a < active_; ++a) {
    const Index j = members_[a];
    y_[a] = delta_[j] / delta_scale_[j];
    rate_[a] = phase_[j] == Phase::expansion ? expansion_rate_[j] : 1.0;
  }
  rhs_velocity_.resize(members_.size());
  velocity_at_.resize(members_.size());
  accounted_impulse_.assign(active_, 0.0);
  accounted_velocity_.resize(active_);
  for (std::size_t a = 0; a < active_; ++a) accounted_velocity_[a] = velocity_[members_[a]];
}

// The contacts' work since the last accounting point, by the trapezoidal rule on u: per contact
// an approximation of the integral of -u_j dP_j, summed over them exact, since u is linear in P
// (the kinetic energy lost to round-off, docs/model.md section 12; docs/design/adaptive_lzb.md).
void LzbAdaptiveIntegrator::Impact::account_work(const State& y) {
  member_velocities(y, velocity_at_);
  for (std::size_t a = 0; a < active_; ++a) {
    const Index j = members_[a];
    const double impulse = y[active_ + a] * impulse_scale_[j];
    work_[j] -=
        0.5 * (accounted_velocity_[a] + velocity_at_[a]) * (impulse - accounted_impulse_[a]);
    accounted_velocity_[a] = velocity_at_[a];
    accounted_impulse_[a] = impulse;
  }
}

void LzbAdaptiveIntegrator::Impact::member_velocities(const State& y,
                                                      std::vector<double>& velocity) const {
  for (std::size_t p = 0; p < members_.size(); ++p) velocity[p] = velocity_[members_[p]];
  const int* start = H_->outerIndexPtr();
  const int* row = H_->innerIndexPtr();
  const double* value = H_->valuePtr();
  for (std::size_t a = 0; a < active_; ++a) {
    const Index j = members_[a];
    const double increment = y[active_ + a] * impulse_scale_[j];
    // (a segment within the steps: its outer ring has neighbours beyond the members, moved by
    // end_segment)
    for (int k = start[j]; k < start[j + 1]; ++k)
      if (const int other = member_of_[row[k]]; other >= 0)
        velocity[std::size_t(other)] += value[k] * increment;
  }
}

double LzbAdaptiveIntegrator::Impact::member_velocity(const State& y, std::size_t member) const {
  return column_velocity(member, [&](std::size_t other) { return y[active_ + other]; });
}

double LzbAdaptiveIntegrator::Impact::member_value(std::size_t member, int kind,
                                                   const State& y) const {
  if (kind == release)
    return y[member] * delta_scale_[members_[member]] - release_level_[members_[member]];
  const double velocity = member_velocity(y, member);
  switch (kind) {
    case join:
      return velocity + velocity_tolerance_;
    case compression_end:
      return -velocity;
    default:  // reload
      return velocity;
  }
}

// d delta_j/dt = -u_j (compression, mono-stiffness expansion) or -u_j / e_j^2 (bi-stiffness
// expansion); dP_j/dt = F_j = K_j delta_j^eta_j. Scaled by each contact's delta and P scales.
void LzbAdaptiveIntegrator::Impact::derivative(const State& y, State& dydt) {
  member_velocities(y, rhs_velocity_);
  for (std::size_t a = 0; a < active_; ++a) {
    const Index j = members_[a];
    dydt[a] = -rhs_velocity_[a] * rate_[a] / delta_scale_[j];
    dydt[active_ + a] = force(j, delta_of(a, y)) / impulse_scale_[j];
  }
}

void LzbAdaptiveIntegrator::Impact::watch(double t, Watched& values) {
  const State* y = &y_at_;
  if (t == ode_.time())
    y = &ode_.state();
  else
    ode_.state_at(t, y_at_);
  values.velocity.resize(members_.size());
  values.delta.resize(active_);
  member_velocities(*y, values.velocity);
  // unclamped, so that a release at delta = 0 is narrowed where delta changes sign
  for (std::size_t a = 0; a < active_; ++a) values.delta[a] = (*y)[a] * delta_scale_[members_[a]];
}

// The quantity that is > 0 before the switch `kind` of a member and <= 0 once it happened.
double LzbAdaptiveIntegrator::Impact::watched_value(std::size_t member, int kind,
                                                    const Watched& values) const {
  switch (kind) {
    case join:
      return values.velocity[member] + velocity_tolerance_;
    case compression_end:
      return -values.velocity[member];
    case reload:
      return values.velocity[member];
    default:  // release
      return values.delta[member] - release_level_[members_[member]];
  }
}

// The switches of [t0, t1], each narrowed (TOMS 748) to a few ulp of t on the dense output.
// Every member is on the near side of its switches when a segment starts, up to rounding.
void LzbAdaptiveIntegrator::Impact::locate(double t0, double t1, const Watched& before,
                                           const Watched& after, std::vector<Crossing>& found) {
  if (within_steps_) {
    locate_turns(t0, t1, before, after);
    return;
  }
  const double resolution = 4.0 * DBL_EPSILON * t1;
  auto check = [&](std::size_t member, int kind) {
    const double q0 = watched_value(member, kind, before);
    const double q1 = watched_value(member, kind, after);
    if (q1 > 0.0 || (q0 <= 0.0 && t0 != segment_start_)) return;
    double crossing = t0;
    if (q0 > 0.0) {
      // this member's value alone: one column of H, not all the members' velocities (a
      // packing keeps hundreds of contacts in the impact, and every narrowing step asked for
      // all of them)
      auto q = [&](double t) {
        ode_.state_at(t, y_at_);
        return member_value(member, kind, y_at_);
      };
      crossing = narrow_crossing(q, t0, t1, q0, q1, resolution).upper;
    }
    found.push_back({long(member), kind, crossing});
  };
  for (std::size_t p = 0; p < members_.size(); ++p) {
    switch (phase_[members_[p]]) {
      case Phase::open:
        check(p, join);
        break;
      case Phase::compression:
        check(p, compression_end);
        break;
      case Phase::expansion:
        check(p, reload);
        check(p, release);
        break;
    }
  }
}

double LzbAdaptiveIntegrator::Impact::member_velocity_at(const DenseOutput::Weights& w,
                                                         std::size_t member) const {
  return column_velocity(member,
                         [&](std::size_t other) { return ode_.component_at(w, active_ + other); });
}

// Where a member's u_j changes sign within [t0, t1], narrowed on its own column of H: a peak
// of delta_j (u_j turning positive) or a closing (negative).
void LzbAdaptiveIntegrator::Impact::locate_turns(double t0, double t1, const Watched& before,
                                                 const Watched& after) {
  const double resolution = 4.0 * DBL_EPSILON * t1;
  for (std::size_t p = 0; p < members_.size(); ++p) {
    const double u0 = before.velocity[p], u1 = after.velocity[p];
    const bool closing = u0 > 0.0 && u1 <= 0.0;
    if (!closing && !(u0 < 0.0 && u1 >= 0.0)) continue;
    const double sign = closing ? 1.0 : -1.0;  // > 0 before the turn
    auto q = [&](double t) { return sign * member_velocity_at(ode_.weights_at(t), p); };
    turns_.push_back(
        {p, narrow_crossing(q, t0, t1, sign * u0, sign * u1, resolution).upper, closing});
  }
}

bool LzbAdaptiveIntegrator::Impact::settle_turns(double t0, double t1) {
  std::stable_sort(turns_.begin(), turns_.end(),
                   [](const Turn& a, const Turn& b) { return a.member < b.member; });
  if (!turns_.empty()) y_settled_ = ode_.state();
  bool changed = false;
  for (auto first = turns_.begin(); first != turns_.end();) {
    const auto last = std::find_if(first, turns_.end(),
                                   [&](const Turn& turn) { return turn.member != first->member; });
    changed = settle_member(t0, t1, {first, last}) || changed;
    first = last;
  }
  turns_.clear();
  return changed;
}

// One member's turns within the step [t0, t1], in time order. The step grew its delta_j at the
// segment's rate, rate_ (from u_j's sign at its start), as if it had not turned. From the first
// turn that changes its law (an inelastic contact's peak or re-loading, where 1 and 1/e^2 swap;
// a separated contact approaching again, its delta_j set back to 0) to the step's end, the
// contact is integrated again alone, to the same tolerance: its delta_j and P_j under its own
// law, its u_j the step's plus what its new impulse changes, H_jj (P_j - P_j of the step); its
// neighbours' impulses as the step found them. Corrected along the step's own velocity instead,
// a lone contact at e = 0.3 landed up to 40 times the tolerance off: the law's change moves the
// contact's own velocity through H_jj, the largest of its column.
bool LzbAdaptiveIntegrator::Impact::settle_member(double t0, double t1,
                                                  std::span<const Turn> turns) {
  namespace odeint = boost::numeric::odeint;
  const std::size_t p = turns.front().member;
  const Index j = members_[p];
  const double scale = delta_scale_[j];
  using Local = std::array<double, 2>;  // delta_j / scale, P_j's increment / impulse scale
  auto alone = [&](const Local& x, Local& dxdt, double t) {
    const DenseOutput::Weights w = ode_.weights_at(t);
    const double u = member_velocity_at(w, p) + self_mobility_[j] * impulse_scale_[j] *
                                                    (x[1] - ode_.component_at(w, active_ + p));
    dxdt[0] = -u * (u > 0.0 ? expansion_rate_[j] : 1.0) / scale;
    dxdt[1] = force(j, std::max(x[0], 0.0) * scale) / impulse_scale_[j];
  };
  auto stepper = odeint::make_controlled<odeint::runge_kutta_dopri5<Local>>(local_tolerance_,
                                                                            local_tolerance_);
  Local x{};
  double from = t0;
  bool alone_since = false;  // integrated alone from `from`
  auto advance = [&](double to) {
    if (to > from) odeint::integrate_adaptive(stepper, alone, x, from, to, 0.25 * (to - from));
    from = to;
  };
  for (const Turn& turn : turns) {
    if (alone_since) advance(turn.time);
    double delta = alone_since ? x[0] : ode_.component_at(ode_.weights_at(turn.time), p);
    if (!turn.closing) {
      if (const double f = force(j, std::max(delta, 0.0) * scale); f > max_force_[j]) {
        max_force_[j] = f;
        time_of_max_[j] = turn.time;
      }
      if (alone_since || expansion_rate_[j] == rate_[p]) continue;  // the law goes on
    } else if (delta < 0.0) {
      delta = 0.0;  // the clamp: delta_j is at its least at the turn and grows from 0 there
    } else if (alone_since || rate_[p] == 1.0) {
      continue;  // re-loading at the rate the step (or the contact alone) already takes
    }
    if (!alone_since) x[1] = ode_.component_at(ode_.weights_at(turn.time), active_ + p);
    x[0] = delta;
    from = turn.time;
    alone_since = true;
  }
  if (!alone_since) return false;
  advance(t1);
  y_settled_[p] = x[0];
  y_settled_[active_ + p] = x[1];
  return true;
}

bool LzbAdaptiveIntegrator::Impact::outgrown(const State& y) const {
  for (std::size_t a = 0; a < active_; ++a)
    if (ring_[a] == 2 && (y[a] > 0.0 || y[active_ + a] != 0.0)) return true;
  return false;
}

// Writes the members' state at the end of the segment (state y) into the per-contact arrays.
void LzbAdaptiveIntegrator::Impact::end_segment(const State& y) {
  member_velocities(y, velocity_at_);
  for (std::size_t p = 0; p < members_.size(); ++p) velocity_[members_[p]] = velocity_at_[p];
  const int* start = H_->outerIndexPtr();
  const int* row = H_->innerIndexPtr();
  const double* value = H_->valuePtr();
  for (std::size_t a = 0; a < active_; ++a) {
    const Index j = members_[a];
    delta_[j] = delta_of(a, y);
    const double increment = y[active_ + a] * impulse_scale_[j];
    impulse_[j] += increment;
    closed_impulse_sum_ += increment;
    if (!within_steps_) continue;
    // the phases a segment that locates its switches starts from
    const double u = velocity_[j];
    phase_[j] = delta_[j] > 0.0            ? (u < 0.0 ? Phase::compression : Phase::expansion)
                : u < -velocity_tolerance_ ? Phase::compression
                                           : Phase::open;
    // an outer ring's contact that loaded within the last step moved contacts beyond the members
    if (ring_[a] == 2 && increment != 0.0)
      for (int k = start[j]; k < start[j + 1]; ++k)
        if (const Index other = row[k]; member_of_[other] < 0) {
          velocity_[other] += value[k] * increment;
          if (velocity_[other] < -velocity_tolerance_ && phase_[other] == Phase::open) {
            phase_[other] = Phase::compression;  // joining
            pending_.push_back(other);
          }
        }
  }
}

void LzbAdaptiveIntegrator::Impact::apply(const std::vector<Crossing>& crossings, double t) {
  for (const Crossing& crossing : crossings) {
    const Index j = members_[std::size_t(crossing.index)];
    switch (crossing.kind) {
      case join:
        phase_[j] = Phase::compression;
        delta_[j] = 0.0;
        break;
      case compression_end:
        if (const double f = force(j, delta_[j]); f > max_force_[j]) {
          max_force_[j] = f;
          time_of_max_[j] = t;
        }
        phase_[j] = gives_nothing_back_[j] ? Phase::open : Phase::expansion;
        if (gives_nothing_back_[j]) delta_[j] = 0.0;
        release_level_[j] = release_factor_[j] * delta_[j];
        break;
      case reload:
        phase_[j] = Phase::compression;
        break;
      default:  // release
        phase_[j] = Phase::open;
        delta_[j] = 0.0;
        break;
    }
  }
}

// The impact's end: no contact approaches faster than tolerance * V and none holds more
// than its energy tolerance (the open ones are known to approach slower: they would have
// joined).
bool LzbAdaptiveIntegrator::Impact::settled(const State& y) {
  member_velocities(y, velocity_at_);
  for (std::size_t a = 0; a < active_; ++a) {
    const Index j = members_[a];
    if (velocity_at_[a] < -velocity_tolerance_ || energy(j, delta_of(a, y)) > energy_tolerance_[j])
      return false;
  }
  return true;
}

void LzbAdaptiveIntegrator::Impact::notify(double t, const State* y, ImpactObserver& observer) {
  if (y) member_velocities(*y, velocity_at_);
  double impulse_sum = closed_impulse_sum_;
  if (y)
    for (std::size_t a = 0; a < active_; ++a)
      impulse_sum += (*y)[active_ + a] * impulse_scale_[members_[a]];
  sampler_->observe(
      observer, steps_, t, impulse_sum,
      [&](Index j, double& u, double& energy_now, double& force_now, double& impulse) {
        const int p = y ? member_of_[j] : -1;
        const bool active = p >= 0 && std::size_t(p) < active_;
        const double delta = active ? delta_of(std::size_t(p), *y) : delta_[j];
        u = p >= 0 ? velocity_at_[std::size_t(p)] : velocity_[j];
        energy_now = energy(j, delta);
        force_now = force(j, delta);
        impulse = impulse_[j] + (active ? (*y)[active_ + std::size_t(p)] * impulse_scale_[j] : 0.0);
      });
}

// The samples of the observer that fall in the part of the current step up to t.
void LzbAdaptiveIntegrator::Impact::sample_until(double t, ImpactObserver& observer) {
  if (sample_interval_ <= 0.0) return;
  for (double next = last_sample_ + sample_interval_; next <= t;
       next = last_sample_ + sample_interval_) {
    ode_.state_at(next, y_at_);
    notify(next, &y_at_, observer);
    last_sample_ = next;
  }
}

void LzbAdaptiveIntegrator::Impact::finish(double t, LzbResult& result) {
  const std::size_t m = phase_.size();
  result.impulse = Eigen::Map<const Eigen::VectorXd>(impulse_.data(), Index(m));
  result.work = Eigen::Map<const Eigen::VectorXd>(work_.data(), Index(m));
  result.stored_energy = Eigen::VectorXd::Zero(Index(m));
  for (std::size_t j = 0; j < m; ++j) {
    if (phase_[j] == Phase::open) continue;
    result.stored_energy(Index(j)) = energy(Index(j), delta_[j]);
    if (const double f = force(Index(j), delta_[j]); f > max_force_[j]) {
      max_force_[j] = f;  // still in compression at the end
      time_of_max_[j] = t;
    }
  }
  result.max_force = Eigen::Map<const Eigen::VectorXd>(max_force_.data(), Index(m));
  result.time_of_max_force = Eigen::Map<const Eigen::VectorXd>(time_of_max_.data(), Index(m));
  result.steps = steps_;
  result.contact_steps = contact_steps_;
  result.duration = t;
}

void LzbAdaptiveIntegrator::Impact::run(const Eigen::SparseMatrix<double>& H,
                                        const Eigen::VectorXd& diagonal,
                                        const Eigen::VectorXd& u_minus, const LawTable& laws,
                                        const LzbAdaptiveOptions& options, ImpactSampler& sampler,
                                        ImpactObserver* observer, LzbResult& result) {
  H_ = &H;
  sampler_ = &sampler;
  prepare(diagonal, u_minus, laws, options);
  begin_segment();
  // the first step: a small share of the time the fastest contact takes to stop
  double first_step = 1.0;
  for (std::size_t a = 0; a < active_; ++a)
    if (u_minus(members_[a]) < 0.0)
      first_step = std::min(first_step, delta_scale_[members_[a]] / -u_minus(members_[a]));
  ode_.restart(y_, 0.0, 1e-3 * first_step);
  if (observer) notify(0.0, &y_, *observer);
  auto rhs = [this](const State& y, State& dydt, double) { derivative(y, dydt); };

  std::int64_t restarts = 0;
  double t = 0.0;
  while (true) {
    if (steps_ + restarts >= options.max_steps) {
      account_work(ode_.state());
      end_segment(ode_.state());
      finish(ode_.time(), result);
      result.status = LzbStatus::step_limit;
      result.message =
          "the impact did not end within max_steps = " + std::to_string(options.max_steps) +
          " steps and restarts";
      if (observer) notify(result.duration, nullptr, *observer);
      return;
    }
    const double step_start = ode_.time();
    ode_.step(rhs);
    ++steps_;
    contact_steps_ += std::int64_t(active_);
    const std::vector<Crossing> found = scan_events(
        step_start, ode_.time(), kSamplesPerStep + 1, 0.0, before_, after_,
        [this](double time, Watched& v) { watch(time, v); },
        [this](double t0, double t1, const Watched& b, const Watched& a, std::vector<Crossing>& f) {
          locate(t0, t1, b, a, f);
        });
    if (found.empty()) {
      t = ode_.time();
      const bool changed = within_steps_ && settle_turns(step_start, t);
      const State& y = changed ? y_settled_ : ode_.state();
      account_work(y);
      if (observer) sample_until(t, *observer);
      const bool grow = within_steps_ && outgrown(y);
      if (!grow && settled(y)) {
        end_segment(y);
        break;
      }
      if (changed || grow) {
        // a state set back, or members to add: the same step goes on from here
        end_segment(y);
        begin_segment();
        if (active_ == 0) break;
        ode_.restart(y_, t, ode_.next_step());
        segment_start_ = t;
      }
      continue;
    }
    t = found.front().time;
    if (observer) sample_until(t, *observer);
    ode_.state_at(t, y_at_);
    account_work(y_at_);
    end_segment(y_at_);
    apply(found, t);
    const double last_step = ode_.last_step();
    begin_segment();
    if (active_ == 0) break;
    ode_.restart(y_, t, last_step);
    segment_start_ = t;
    ++restarts;
  }
  finish(t, result);
  if (observer) notify(t, nullptr, *observer);
}

LzbAdaptiveIntegrator::LzbAdaptiveIntegrator(LzbAdaptiveOptions options)
    : ImpactIntegrator(options.sampled_contacts), options_(std::move(options)) {
  validate(options_, "adaptive LZB options");
}

LzbAdaptiveIntegrator::~LzbAdaptiveIntegrator() = default;
LzbAdaptiveIntegrator::LzbAdaptiveIntegrator(LzbAdaptiveIntegrator&&) noexcept = default;
LzbAdaptiveIntegrator& LzbAdaptiveIntegrator::operator=(LzbAdaptiveIntegrator&&) noexcept = default;

void LzbAdaptiveIntegrator::set_tolerance(double tolerance) {
  LzbAdaptiveOptions changed = options_;
  changed.tolerance = tolerance;
  validate(changed, "adaptive LZB options");
  options_ = std::move(changed);
  impact_.reset();
}

Eigen::VectorXd LzbAdaptiveIntegrator::velocity_resolution(const Eigen::VectorXd& diagonal,
                                                           const Eigen::VectorXd& u_minus) const {
  return Eigen::VectorXd::Constant(diagonal.size(), options_.tolerance * (-u_minus.minCoeff()));
}

void LzbAdaptiveIntegrator::run(const Input& input, ImpactObserver* observer, LzbResult& result) {
  if (!impact_) impact_ = std::make_unique<Impact>(options_.tolerance);
  impact_->run(input.H, input.diagonal, input.u_minus, input.laws, options_, sampler(), observer,
               result);
}

}  // namespace mimpact::numerics
