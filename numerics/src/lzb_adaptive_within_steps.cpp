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
  for (Index j : segment_.members) contact_.member_of[j] = -1;
  std::vector<Index>& previous = segment_.previous_members;
  previous.swap(segment_.members);
  segment_.members.clear();
  within_.ring.clear();
  auto take = [&](Index j, unsigned char ring) {
    contact_.member_of[j] = int(segment_.members.size());
    segment_.members.push_back(j);
    within_.ring.push_back(ring);
  };
  auto core = [&](Index j) { return contact_.member_of[j] < 0 && takes_part(j); };
  if (previous.empty() && within_.pending.empty()) {  // the first segment
    for (Index j = 0; j < Index(contact_.phase.size()); ++j)
      if (core(j)) take(j, 0);
  }
  for (Index j : previous)
    if (core(j)) take(j, 0);
  for (Index j : within_.pending)
    if (core(j)) take(j, 0);
  within_.pending.clear();
  const int* start = H_->outerIndexPtr();
  const int* row = H_->innerIndexPtr();
  std::size_t ring_start = 0;
  for (unsigned char ring = 1; ring <= 2; ++ring) {
    const std::size_t ring_end = segment_.members.size();
    for (std::size_t a = ring_start; a < ring_end; ++a)
      for (int k = start[segment_.members[a]]; k < start[segment_.members[a] + 1]; ++k)
        if (contact_.member_of[row[k]] < 0) take(row[k], ring);
    ring_start = ring_end;
  }
  segment_.active = segment_.members.size();
  size_segment();
}

double adaptive_lzb::Impact::member_velocity_at(const DenseOutput::Weights& w,
                                                std::size_t member) const {
  return column_velocity(
      member, [&](std::size_t other) { return ode_.component_at(w, segment_.active + other); });
}

// Where a member's u_j changes sign within [t0, t1], narrowed on its own column of H: a peak
// of delta_j (u_j turning positive) or a closing (negative).
void adaptive_lzb::Impact::locate_turns(double t0, double t1, const Watched& before,
                                        const Watched& after) {
  const double resolution = 4.0 * DBL_EPSILON * t1;
  for (std::size_t p = 0; p < segment_.members.size(); ++p) {
    const double u0 = before.velocity[p], u1 = after.velocity[p];
    const bool closing = u0 > 0.0 && u1 <= 0.0;
    if (!closing && !(u0 < 0.0 && u1 >= 0.0)) continue;
    const double sign = closing ? 1.0 : -1.0;  // > 0 before the turn
    auto q = [&](double t) { return sign * member_velocity_at(ode_.weights_at(t), p); };
    within_.turns.push_back(
        {p, narrow_crossing(q, t0, t1, sign * u0, sign * u1, resolution).upper, closing});
  }
}

bool adaptive_lzb::Impact::settle_turns(double t0, double t1) {
  std::stable_sort(within_.turns.begin(), within_.turns.end(),
                   [](const Turn& a, const Turn& b) { return a.member < b.member; });
  if (!within_.turns.empty()) within_.y_settled = ode_.state();
  bool changed = false;
  for (auto first = within_.turns.begin(); first != within_.turns.end();) {
    const auto last = std::find_if(first, within_.turns.end(),
                                   [&](const Turn& turn) { return turn.member != first->member; });
    changed = settle_member(t0, t1, {first, last}) || changed;
    first = last;
  }
  within_.turns.clear();
  return changed;
}

// One member's turns within the step [t0, t1], in time order. The step grew its delta_j at the
// segment's rate, segment_.rate (from u_j's sign at its start), as if it had not turned. From the
// first turn that changes its law (an inelastic contact's peak or re-loading, where 1 and 1/e^2
// swap; a separated contact approaching again, its delta_j set back to 0) to the step's end, the
// contact is integrated again alone, to the same tolerance: its delta_j and P_j under its own
// law, its u_j the step's plus what its new impulse changes, H_jj (P_j - P_j of the step); its
// neighbours' impulses as the step found them. Corrected along the step's own velocity instead,
// a lone contact at e = 0.3 landed up to 40 times the tolerance off: the law's change moves the
// contact's own velocity through H_jj, the largest of its column.
bool adaptive_lzb::Impact::settle_member(double t0, double t1, std::span<const Turn> turns) {
  namespace odeint = boost::numeric::odeint;
  const std::size_t p = turns.front().member;
  const Index j = segment_.members[p];
  const double scale = law_.delta_scale[j];
  using Local = std::array<double, 2>;  // delta_j / scale, P_j's increment / impulse scale
  auto alone = [&](const Local& x, Local& dxdt, double t) {
    const DenseOutput::Weights w = ode_.weights_at(t);
    const double u =
        member_velocity_at(w, p) + law_.self_mobility[j] * law_.impulse_scale[j] *
                                       (x[1] - ode_.component_at(w, segment_.active + p));
    dxdt[0] = -u * (u > 0.0 ? law_.expansion_rate[j] : 1.0) / scale;
    dxdt[1] = force(j, std::max(x[0], 0.0) * scale) / law_.impulse_scale[j];
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
      if (const double f = force(j, std::max(delta, 0.0) * scale); f > contact_.max_force[j]) {
        contact_.max_force[j] = f;
        contact_.time_of_max[j] = turn.time;
      }
      if (alone_since || law_.expansion_rate[j] == segment_.rate[p]) continue;  // the law goes on
    } else if (delta < 0.0) {
      delta = 0.0;  // the clamp: delta_j is at its least at the turn and grows from 0 there
    } else if (alone_since || segment_.rate[p] == 1.0) {
      continue;  // re-loading at the rate the step (or the contact alone) already takes
    }
    if (!alone_since) x[1] = ode_.component_at(ode_.weights_at(turn.time), segment_.active + p);
    x[0] = delta;
    from = turn.time;
    alone_since = true;
  }
  if (!alone_since) return false;
  advance(t1);
  within_.y_settled[p] = x[0];
  within_.y_settled[segment_.active + p] = x[1];
  return true;
}

bool adaptive_lzb::Impact::outgrown(const State& y) const {
  for (std::size_t a = 0; a < segment_.active; ++a)
    if (within_.ring[a] == 2 && (y[a] > 0.0 || y[segment_.active + a] != 0.0)) return true;
  return false;
}

}  // namespace mimpact::numerics
