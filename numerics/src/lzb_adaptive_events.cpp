#include <algorithm>
#include <cmath>
#include <vector>

#include "lzb_adaptive_impact.hpp"
#include "mimpact/numerics/event_scan.hpp"

// The adaptive LZB's switches located as events (docs/design/adaptive_lzb.md): each member's
// watched quantity sampled over a step and its crossings narrowed by TOMS 748 on the dense
// output.
namespace mimpact::numerics {

using Eigen::Index;
using namespace adaptive_lzb;  // the impact's phases, switches and constants

double adaptive_lzb::Impact::member_velocity(const State& y, std::size_t member) const {
  const double velocity = shared_.column_velocity(
      member, [&](std::size_t other) { return y[shared_.segment.active + other]; });
  if (!friction_.on()) return velocity;
  return velocity + friction_.normal_increment(y, shared_.segment.members[member]);
}

double adaptive_lzb::Impact::member_value(std::size_t member, int kind, const State& y) const {
  if (kind == release)
    return y[member] * shared_.law.delta_scale[shared_.segment.members[member]] -
           shared_.contact.release_level[shared_.segment.members[member]];
  const double velocity = member_velocity(y, member);
  switch (kind) {
    case join:
      return velocity + shared_.velocity_tolerance;
    case compression_end:
      return -velocity;
    default:  // reload
      return velocity;
  }
}

// The members' velocities and the active ones' delta_j at t, on the dense output.
void adaptive_lzb::Impact::watch(double t, Watched& values) {
  const State* y = &shared_.segment.y_at;
  if (t == ode_.time())
    y = &ode_.state();
  else
    ode_.state_at(t, shared_.segment.y_at);
  values.velocity.resize(shared_.segment.members.size());
  values.delta.resize(shared_.segment.active);
  member_velocities(*y, values.velocity);
  // unclamped, so that a release at delta = 0 is narrowed where delta changes sign
  for (std::size_t a = 0; a < shared_.segment.active; ++a)
    values.delta[a] = (*y)[a] * shared_.law.delta_scale[shared_.segment.members[a]];
  if (friction_.on()) friction_.watch(*y, values.friction);
}

// The switches of [t0, t1], each narrowed (TOMS 748) to a few ulp of t on the dense output.
// Every member is on the near side of its switches when a segment starts, up to rounding.
void adaptive_lzb::Impact::locate(double t0, double t1, const Watched& before, const Watched& after,
                                  std::vector<Crossing>& found) {
  if (within_.on()) {
    within_.locate_turns(t0, t1, before, after);
    return;
  }
  auto check = [&](std::size_t member, int kind) {
    // this member's value alone: one column of H, not all the members' velocities (a packing
    // keeps hundreds of contacts in the impact, and every narrowing step asked for all of them)
    auto q = [&](double t) {
      ode_.state_at(t, shared_.segment.y_at);
      return member_value(member, kind, shared_.segment.y_at);
    };
    if (const std::optional<double> crossing =
            crossing_time(watched_value(member, kind, before), watched_value(member, kind, after),
                          t0, t1, segment_start_, q))
      found.push_back({long(member), kind, *crossing});
  };
  for (std::size_t p = 0; p < shared_.segment.members.size(); ++p) {
    switch (shared_.contact.phase[shared_.segment.members[p]]) {
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
  if (friction_.on())
    friction_.locate(t0, t1, segment_start_, before.friction, after.friction, found);
}

}  // namespace mimpact::numerics
