#include <algorithm>
#include <array>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <span>
#include <vector>

#include "lzb_adaptive_within_steps.hpp"
#include "mimpact/numerics/root_bracketing.hpp"

// The adaptive LZB's switches kept within its steps (docs/design/adaptive_lzb.md): when a
// segment keeps them, its members, the turns found within a step and each turning contact
// integrated again alone.
namespace mimpact::numerics::adaptive_lzb {

using Eigen::Index;

void WithinSteps::prepare(const LawTable& laws, std::size_t from) {
  pending_.clear();
  continuous_laws_ = laws.size() > 0;
  for (std::size_t j = 0; j < laws.size(); ++j)
    continuous_laws_ = continuous_laws_ && (laws[j].restitution == 1.0 ||
                                            (!laws[j].mono_stiffness && laws[j].restitution > 0.0));
  on_ = false;
  enter_ = from;
  leave_ = enter_ / 2;
}

bool WithinSteps::choose() {
  if (!continuous_laws_) return false;
  const Segment& segment = impact_.segment;
  std::size_t core = 0;
  auto count = [&](Index j) { core += impact_.takes_part(j); };
  if (segment.members.empty())
    for (Index j = 0; j < Index(impact_.contact.phase.size()); ++j) count(j);
  for (Index j : segment.members) count(j);
  core += pending_.size();
  on_ = core >= (on_ ? leave_ : enter_);
  return on_;
}

void WithinSteps::hand_pending(std::vector<Index>& members) {
  members.insert(members.end(), pending_.begin(), pending_.end());
  pending_.clear();
}

// The members of a segment within the steps: the contacts holding energy or approaching faster than
// tolerance * V, then the ring of their neighbours through H, then the ring of those: a
// contact of the first ring may load within a step, and its impulse then moves only members.
void WithinSteps::begin_segment() {
  Segment& segment = impact_.segment;
  ContactStates& contact = impact_.contact;
  for (Index j : segment.members) contact.member_of[j] = -1;
  std::vector<Index>& previous = segment.previous_members;
  previous.swap(segment.members);
  segment.members.clear();
  ring_.clear();
  auto take = [&](Index j, unsigned char ring) {
    contact.member_of[j] = int(segment.members.size());
    segment.members.push_back(j);
    ring_.push_back(ring);
  };
  auto core = [&](Index j) { return contact.member_of[j] < 0 && impact_.takes_part(j); };
  if (previous.empty() && pending_.empty()) {  // the first segment
    for (Index j = 0; j < Index(contact.phase.size()); ++j)
      if (core(j)) take(j, 0);
  }
  for (Index j : previous)
    if (core(j)) take(j, 0);
  for (Index j : pending_)
    if (core(j)) take(j, 0);
  pending_.clear();
  const int* start = impact_.H->outerIndexPtr();
  const int* row = impact_.H->innerIndexPtr();
  std::size_t ring_start = 0;
  for (unsigned char ring = 1; ring <= 2; ++ring) {
    const std::size_t ring_end = segment.members.size();
    for (std::size_t a = ring_start; a < ring_end; ++a)
      for (int k = start[segment.members[a]]; k < start[segment.members[a] + 1]; ++k)
        if (contact.member_of[row[k]] < 0) take(row[k], ring);
    ring_start = ring_end;
  }
  segment.active = segment.members.size();
}

void WithinSteps::end_member(std::size_t a, double increment) {
  ContactStates& contact = impact_.contact;
  const Index j = impact_.segment.members[a];
  // the phases a segment that locates its switches starts from
  const double u = contact.velocity[j];
  contact.phase[j] = contact.delta[j] > 0.0 ? (u < 0.0 ? Phase::compression : Phase::expansion)
                     : u < -impact_.velocity_tolerance ? Phase::compression
                                                       : Phase::open;
  if (ring_[a] != 2 || increment == 0.0) return;
  // an outer ring's contact that loaded within the last step moved contacts beyond the members
  const int* start = impact_.H->outerIndexPtr();
  const int* row = impact_.H->innerIndexPtr();
  const double* value = impact_.H->valuePtr();
  for (int k = start[j]; k < start[j + 1]; ++k)
    if (const Index other = row[k]; contact.member_of[other] < 0) {
      contact.velocity[other] += value[k] * increment;
      if (contact.velocity[other] < -impact_.velocity_tolerance &&
          contact.phase[other] == Phase::open) {
        contact.phase[other] = Phase::compression;  // joining
        pending_.push_back(other);
      }
    }
}

double WithinSteps::member_velocity_at(const DenseOutput::Weights& w, std::size_t member) const {
  const Segment& segment = impact_.segment;
  return impact_.column_velocity(
      member, [&](std::size_t other) { return ode_.component_at(w, segment.active + other); });
}

// Where a member's u_j changes sign within [t0, t1], narrowed on its own column of H: a peak
// of delta_j (u_j turning positive) or a closing (negative).
void WithinSteps::locate_turns(double t0, double t1, const Watched& before, const Watched& after) {
  const Segment& segment = impact_.segment;
  const double resolution = 4.0 * DBL_EPSILON * t1;
  for (std::size_t p = 0; p < segment.members.size(); ++p) {
    const double u0 = before.velocity[p], u1 = after.velocity[p];
    const bool closing = u0 > 0.0 && u1 <= 0.0;
    if (!closing && !(u0 < 0.0 && u1 >= 0.0)) continue;
    const double sign = closing ? 1.0 : -1.0;  // > 0 before the turn
    auto q = [&](double t) { return sign * member_velocity_at(ode_.weights_at(t), p); };
    turns_.push_back(
        {p, narrow_crossing(q, t0, t1, sign * u0, sign * u1, resolution).upper, closing});
  }
}

bool WithinSteps::settle_turns(double t0, double t1) {
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
// segment's rate (from u_j's sign at its start), as if it had not turned. From the
// first turn that changes its law (an inelastic contact's peak or re-loading, where 1 and 1/e^2
// swap; a separated contact approaching again, its delta_j set back to 0) to the step's end, the
// contact is integrated again alone, to the same tolerance: its delta_j and P_j under its own
// law, its u_j the step's plus what its new impulse changes, H_jj (P_j - P_j of the step); its
// neighbours' impulses as the step found them: the law's change moves the contact's own velocity
// through H_jj, the largest of its column (docs/design/adaptive_lzb.md, "Trials not kept").
bool WithinSteps::settle_member(double t0, double t1, std::span<const Turn> turns) {
  const Segment& segment = impact_.segment;
  const ContactConstants& law = impact_.law;
  ContactStates& contact = impact_.contact;
  namespace odeint = boost::numeric::odeint;
  const std::size_t p = turns.front().member;
  const Index j = segment.members[p];
  const double scale = law.delta_scale[j];
  using Local = std::array<double, 2>;  // delta_j / scale, P_j's increment / impulse scale
  auto alone = [&](const Local& x, Local& dxdt, double t) {
    const DenseOutput::Weights w = ode_.weights_at(t);
    const double u =
        member_velocity_at(w, p) + law.self_mobility[j] * law.impulse_scale[j] *
                                       (x[1] - ode_.component_at(w, segment.active + p));
    dxdt[0] = -u * (u > 0.0 ? law.expansion_rate[j] : 1.0) / scale;
    dxdt[1] = law.force(j, std::max(x[0], 0.0) * scale) / law.impulse_scale[j];
  };
  auto stepper = odeint::make_controlled<odeint::runge_kutta_dopri5<Local>>(
      impact_.local_tolerance, impact_.local_tolerance);
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
      if (const double f = law.force(j, std::max(delta, 0.0) * scale); f > contact.max_force[j]) {
        contact.max_force[j] = f;
        contact.time_of_max[j] = turn.time;
      }
      if (alone_since || law.expansion_rate[j] == segment.rate[p]) continue;  // the law goes on
    } else if (delta < 0.0) {
      delta = 0.0;  // the clamp: delta_j is at its least at the turn and grows from 0 there
    } else if (alone_since || segment.rate[p] == 1.0) {
      continue;  // re-loading at the rate the step (or the contact alone) already takes
    }
    if (!alone_since) x[1] = ode_.component_at(ode_.weights_at(turn.time), segment.active + p);
    x[0] = delta;
    from = turn.time;
    alone_since = true;
  }
  if (!alone_since) return false;
  advance(t1);
  y_settled_[p] = x[0];
  y_settled_[segment.active + p] = x[1];
  return true;
}

bool WithinSteps::outgrown(const State& y) const {
  const Segment& segment = impact_.segment;
  for (std::size_t a = 0; a < segment.active; ++a)
    if (ring_[a] == 2 && (y[a] > 0.0 || y[segment.active + a] != 0.0)) return true;
  return false;
}

}  // namespace mimpact::numerics::adaptive_lzb
