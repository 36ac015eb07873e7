#include <algorithm>
#include <cmath>

#include "mimpact/numerics/event_scan.hpp"
#include "mimpact/numerics/root_bracketing.hpp"
#include "moving_group.hpp"

// A group's events (docs/design/moving_geometry.md, "Bodies in free flight, and groups"): the
// gaps and rates of its contacts and of the bodies flying freely it watches, the entries that
// may touch within a segment, and the earliest touch, located by TOMS 748.
namespace mimpact::granular {

using numerics::ContactEvent;

namespace {

struct GapRate {
  double gap, rate;  // m, m/s
};

// gap and rate of a sphere at xa moving at va against one at xb moving at vb, the two touching
// at distance `reach`
GapRate sphere_gap(const Eigen::Vector3d& xa, const Eigen::Vector3d& va, const Eigen::Vector3d& xb,
                   const Eigen::Vector3d& vb, double reach) {
  const Eigen::Vector3d between = xb - xa;
  const double distance = between.norm();
  return {distance - reach, between.dot(vb - va) / distance};
}

// The cubic Hermite of a gap over a step of length h (s = (t - t0) / h in [0, 1]), from its gaps
// g (m) and rates r (m/s) at both ends, where the rates differ in sign (r0 != 0): where its rate
// changes sign, and its gap there. It places an elastic contact's smallest gap to h^4 / 384
// times the gap's fourth derivative.
struct HermiteTurn {
  double s = 0.0, gap = 0.0;
};
// The Hermite's rate: dg/dt = (A s^2 + B s + C) / h, C = h r0.
struct HermiteRate {
  double A, B, C;
  HermiteRate(double g0, double r0, double g1, double r1, double h)
      : A(6.0 * (g0 - g1) + 3.0 * h * (r0 + r1)),
        B(6.0 * (g1 - g0) - h * (4.0 * r0 + 2.0 * r1)),
        C(h * r0) {}
};
HermiteTurn hermite_turn(double g0, double r0, double g1, double r1, double h) {
  const auto [A, B, C] = HermiteRate(g0, r0, g1, r1, h);
  double s;
  if (std::abs(A) <= 1e-12 * (std::abs(B) + std::abs(C))) {
    s = -C / B;
  } else {  // the root where the rate leaves r0's sign, without cancellation
    const double q = -0.5 * (B + std::copysign(std::sqrt(std::max(B * B - 4.0 * A * C, 0.0)), B));
    const double x1 = q / A, x2 = q != 0.0 ? C / q : x1;
    auto turning = [&](double x) { return x >= 0.0 && x <= 1.0 && (2.0 * A * x + B) * r0 <= 0.0; };
    s = turning(x1) ? x1 : x2;
  }
  s = std::clamp(s, 0.0, 1.0);
  return {s, (1.0 - s) * (1.0 - s) * ((1.0 + 2.0 * s) * g0 + s * h * r0) +
                 s * s * ((3.0 - 2.0 * s) * g1 - (1.0 - s) * h * r1)};
}

}  // namespace

// m: a wall contact's bead above its wall at the last restart
double MovingGroup::wall_height(const Contact& c) const {
  const Plane& wall = world_.geometry.walls[std::size_t(-1 - c.second)];
  const MovingBody& bead = world_.bodies[std::size_t(c.first_body)];
  return wall.normal.dot(bead.anchor - wall.point) +
         wall.normal.dot(state_.origin[std::size_t(c.first)]);
}

// On every elastic contact at every step: read from the state directly.
void MovingGroup::contact_gap(const Contact& c, const double* y, double& gap, double& rate) const {
  const int d = dimension_;
  const std::size_t velocities = std::size_t(d) * members_.size();
  const std::size_t a = std::size_t(d) * std::size_t(c.first);
  const double* origin_a = state_.origin[std::size_t(c.first)].data();
  const double inverse_time_scale = 1.0 / world_.time_scale;
  if (c.second < 0) {
    const Plane& wall = world_.geometry.walls[std::size_t(-1 - c.second)];
    double height = wall_height(c), speed = 0.0;
    for (int k = 0; k < d; ++k) {  // as the right-hand side forms it
      height += wall.normal(k) * y[a + k];
      speed += wall.normal(k) * y[velocities + a + k];
    }
    gap = height - c.reach;
    rate = speed * inverse_time_scale;
    return;
  }
  const std::size_t b = std::size_t(d) * std::size_t(c.second);
  const double* origin_b = state_.origin[std::size_t(c.second)].data();
  double between[3], squared = 0.0, closing = 0.0;
  for (int k = 0; k < d; ++k) {  // as the right-hand side forms it
    between[k] = (c.anchor_offset[k] + (origin_b[k] - origin_a[k])) + (y[b + k] - y[a + k]);
    squared += between[k] * between[k];
    closing += between[k] * (y[velocities + b + k] - y[velocities + a + k]);
  }
  const double distance = std::sqrt(squared);
  gap = distance - c.reach;
  rate = closing * inverse_time_scale / distance;
}

void MovingGroup::watch_gap(const Watch& w, double t, const double* y, double& gap,
                            double& rate) const {
  Eigen::Vector3d xa, va;
  member_state(std::size_t(w.member), y, xa, va);
  const MovingBody& o = world_.bodies[std::size_t(w.other)];
  const GapRate between = sphere_gap(
      xa, va, o.position_at(t), o.v,
      world_.geometry.radius(members_[std::size_t(w.member)]) + world_.geometry.radius(w.other));
  gap = between.gap;
  rate = between.rate;
}

// The member a watched body's entry reads, written into probe_ from the dense output at w's
// time: an event search reads that, not the whole state.
template <class Stepper>
void MovingGroup::probe_entry(const Stepper& stepper, std::size_t entry,
                              const typename Stepper::Weights& w) {
  const std::size_t n = members_.size();
  const auto d = std::size_t(dimension_);
  for (std::size_t i = d * std::size_t(search_.watched[entry].member), end = i + d; i < end; ++i) {
    probe_[i] = stepper.component_at(w, i);
    probe_[d * n + i] = stepper.component_at(w, d * n + i);
  }
}

void MovingGroup::probe_entry_at(std::size_t entry, double t) {
  if (rough_) return probe_entry(*rough_, entry, rough_->weights_at(t));
  probe_entry(*dense_, entry, dense_->weights_at(t));
}

// At the step's end, where most are taken, the entries read the step's own state, not its dense
// output (docs/design/moving_geometry.md, "Peaks, events and the right-hand side").
void MovingGroup::measure(double t, const std::vector<std::size_t>& entries, Samples& samples) {
  samples.gap.resize(entries.size());
  samples.rate.resize(entries.size());
  if (t == stepper_time()) {
    for (std::size_t k = 0; k < entries.size(); ++k)
      watch_gap(search_.watched[entries[k]], t, stepper_state().data(), samples.gap[k],
                samples.rate[k]);
    return;
  }
  auto probe_all = [&](const auto& stepper) {
    const auto w = stepper.weights_at(t);
    for (std::size_t k = 0; k < entries.size(); ++k) {
      probe_entry(stepper, entries[k], w);
      watch_gap(search_.watched[entries[k]], t, probe_.data(), samples.gap[k], samples.rate[k]);
    }
  };
  if (rough_) {
    probe_all(*rough_);
  } else {
    probe_all(*dense_);
  }
}

// Whether entry k, its gap and rate sampled at both ends of [a, b], may reach the touch
// within: it does at an end (classify), or the cubic Hermite of its gap turns inside and
// reaches the threshold give or take the turn's depth (a dip that the cubic misses by its whole
// depth is not a dip the step resolves).
bool MovingGroup::suspect(std::size_t k, double h, const numerics::Overlaps& overlaps) const {
  const double g0 = search_.start_samples.gap[k], g1 = search_.end_samples.gap[k],
               r0 = search_.start_samples.rate[k], r1 = search_.end_samples.rate[k];
  // An open entry's one event is its gap reaching -overlaps.join. The cubic Hermite lies at most
  // 4/27 h (|r0| + |r1|) below the smaller end (its rate terms' bound on [0, 1]); twice that, as
  // the dip's margin below, still above the threshold: no event. Touching beads barely moving
  // (gaps of round-off, rates of 1e-13 m/s) were half of every step's entries, each searched.
  if (std::min(g0, g1) - (8.0 / 27.0) * h * (std::abs(r0) + std::abs(r1)) > -overlaps.join)
    return false;
  const numerics::ContactWatch ends{
      .gap_before = g0, .gap_after = g1, .rate_before = r0, .rate_after = r1};
  if (numerics::classify(ends, overlaps).kind != ContactEvent::none) return true;
  if (r0 * r1 < 0.0) {
    const HermiteTurn turn = hermite_turn(g0, r0, g1, r1, h);
    return turn.gap - (std::min(g0, g1) - turn.gap) <= -overlaps.join;
  }
  // both ends' rates alike: suspect if the rate's own extremum inside is of the other sign
  const auto [A, B, C] = HermiteRate(g0, r0, g1, r1, h);
  const double vertex = A != 0.0 ? -B / (2.0 * A) : -1.0;
  return vertex > 0.0 && vertex < 1.0 && (A * vertex * vertex + B * vertex + C) * r0 < 0.0;
}

// The earliest event of the watched entries in [a, b] of the current step: a body flying freely
// touched (numerics::classify, as the compliant integrator); located by TOMS 748.
bool MovingGroup::next_event(double a, double b, Event& event) {
  if (search_.watched.empty()) return false;
  const numerics::OdeOptions& ode = world_.options.ode;
  const numerics::Overlaps overlaps{.join = world_.options.overlap_resolution,
                                    .leave = 0.5 * world_.options.overlap_resolution};
  // every entry at the segment's ends, its start kept from the segment before
  if (search_.sampled_at != a) measure(a, search_.entries, search_.start_samples);
  measure(b, search_.entries, search_.end_samples);
  search_.suspects.clear();
  for (std::size_t k = 0; k < search_.entries.size(); ++k)
    if (suspect(k, b - a, overlaps)) search_.suspects.push_back(search_.entries[k]);
  std::swap(search_.start_samples, search_.end_samples);
  search_.sampled_at = b;
  if (search_.suspects.empty()) return false;
  // the suspects searched as the compliant integrator searches: at samples_per_step cuts
  search_.one.gap.resize(1);
  search_.one.rate.resize(1);
  auto locate = [&](double t0, double t1, const Samples& s0, const Samples& s1,
                    std::vector<numerics::Crossing>& found) {
    for (std::size_t k = 0; k < search_.suspects.size(); ++k) {
      const std::size_t entry = search_.suspects[k];
      const numerics::ContactWatch w{.gap_before = s0.gap[k],
                                     .gap_after = s1.gap[k],
                                     .rate_before = s0.rate[k],
                                     .rate_after = s1.rate[k]};
      const numerics::Classified crossed = numerics::classify(w, overlaps);
      if (crossed.kind == ContactEvent::none) continue;
      if (crossed.at_start) {
        found.push_back({long(entry), int(crossed.kind), t0});
        continue;
      }
      auto value = [&](double gap, double rate) {
        return numerics::event_function(crossed.kind, gap, rate, overlaps);
      };
      const numerics::Bracket bracket = numerics::narrow_crossing(
          [&](double t) {
            probe_entry_at(entry, t);
            watch_gap(search_.watched[entry], t, probe_.data(), search_.one.gap[0],
                      search_.one.rate[0]);
            return value(search_.one.gap[0], search_.one.rate[0]);
          },
          t0, t1, value(s0.gap[k], s0.rate[k]), value(s1.gap[k], s1.rate[k]), ode.event_tolerance);
      found.push_back({long(entry), int(crossed.kind), bracket.upper});
    }
  };
  const auto found = numerics::scan_events(
      {.start = a, .end = b, .samples = ode.samples_per_step, .tolerance = ode.event_tolerance},
      search_.before, search_.after, [&](double t, Samples& s) { measure(t, search_.suspects, s); },
      locate);
  if (found.empty()) return false;
  const auto earliest = std::min_element(
      found.begin(), found.end(), [](const auto& p, const auto& q) { return p.time < q.time; });
  event = {std::size_t(earliest->index), earliest->time};
  // every body found touching within the same cut is taken with it, one restart for the many a
  // symmetric front touches at once (taken early, a body's contact is integrated from its open
  // gap)
  search_.taken.clear();
  for (const auto& crossing : found)
    search_.taken.push_back(search_.watched[std::size_t(crossing.index)].other);
  return true;
}

}  // namespace mimpact::granular
