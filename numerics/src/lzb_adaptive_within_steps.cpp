#include <algorithm>
#include <array>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <span>
#include <vector>

#include "lzb_adaptive_impact.hpp"
#include "mimpact/numerics/root_bracketing.hpp"

// The adaptive LZB's switches kept within its steps (docs/design/adaptive_lzb.md): the members
// of such a segment, the turns found within a step and each turning contact integrated again
// alone.
namespace mimpact::numerics {

using Eigen::Index;
using namespace adaptive_lzb;  // the impact's phases, switches and constants

// The members of a segment within the steps: the contacts holding energy or approaching faster than
// tolerance * V, then the ring of their neighbours through H, then the ring of those: a
// contact of the first ring may load within a step, and its impulse then moves only members.
void adaptive_lzb::Impact::begin_within_steps_segment() {
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

double adaptive_lzb::Impact::member_velocity_at(const DenseOutput::Weights& w,
                                                std::size_t member) const {
  return column_velocity(member,
                         [&](std::size_t other) { return ode_.component_at(w, active_ + other); });
}

// Where a member's u_j changes sign within [t0, t1], narrowed on its own column of H: a peak
// of delta_j (u_j turning positive) or a closing (negative).
void adaptive_lzb::Impact::locate_turns(double t0, double t1, const Watched& before,
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

bool adaptive_lzb::Impact::settle_turns(double t0, double t1) {
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
bool adaptive_lzb::Impact::settle_member(double t0, double t1, std::span<const Turn> turns) {
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

bool adaptive_lzb::Impact::outgrown(const State& y) const {
  for (std::size_t a = 0; a < active_; ++a)
    if (ring_[a] == 2 && (y[a] > 0.0 || y[active_ + a] != 0.0)) return true;
  return false;
}

}  // namespace mimpact::numerics
