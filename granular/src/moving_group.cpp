#include "moving_group.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "mimpact/common/error.hpp"
#include "mimpact/numerics/event_scan.hpp"
#include "mimpact/numerics/onset_quadrature.hpp"
#include "mimpact/numerics/root_bracketing.hpp"

// One group's integration over a window: M x'' = sum of its loaded contacts' forces along the
// current normals, the Runge-Kutta-Nystrom pair RKN4(3)4FM on (displacements from the last
// restart, velocities, impulses), restarted where it takes a body flying freely
// (docs/design/moving_geometry.md).
namespace mimpact::granular {

using numerics::ContactEvent;

namespace {

Eigen::Vector3d read(const double* y, int dimension) {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int k = 0; k < dimension; ++k) x(k) = y[k];
  return x;
}

// N: an elastic Hertz contact's force K delta^(3/2) at an overlap >= 0 (m), as
// ContactLaw::force forms it, written once for the right-hand side and the peaks alike
double hertz_force(double stiffness, double overlap) {
  return stiffness * (overlap * std::sqrt(overlap));
}

}  // namespace

void MovingGroup::add_member(std::int32_t body) {
  MovingBody& b = world_.bodies[std::size_t(body)];
  b.owner = id_;
  b.slot = std::int32_t(members_.size());
  members_.push_back(body);
  position_.push_back(b.position_at(time_));
  shift_.push_back(b.shift_at(time_));
  velocity_.push_back(b.v);
}

void MovingGroup::recall(Contact& c) const {
  const MovingContact* record =
      c.world_id >= 0 ? &world_.contacts[std::size_t(c.world_id)] : nullptr;
  c.loaded = record && record->joined;
  c.max_compression = record ? record->max_compression : 0.0;
  c.impulse = record ? record->impulse : 0.0;
  c.max_force = record ? record->max_force : 0.0;
  c.time_of_max_force = record ? record->time_of_max_force : 0.0;
  c.dissipated = record ? record->dissipated : 0.0;
}

void MovingGroup::add_contact(std::int32_t first_body, std::int32_t second_body) {
  if (second_body >= 0 && second_body < first_body) std::swap(first_body, second_body);
  Contact c;
  c.world_id = world_.find_contact_id(first_body, second_body);
  if (c.world_id >= 0)
    c.law = world_.contacts[std::size_t(c.world_id)].law;
  else
    c.law = second_body >= 0 ? world_.geometry.bead_law(first_body, second_body)
                             : world_.geometry.wall_law(first_body, std::size_t(-1 - second_body));
  recall(c);
  c.first_body = first_body;
  c.second_body = second_body;
  const Eigen::VectorXd& radius = world_.geometry.radius;
  c.reach = radius(first_body) + (second_body >= 0 ? radius(second_body) : 0.0);
  contacts_.push_back(c);
}

// The lists do not change within a window: a pair of members is found once, when the later of
// the two joins.
void MovingGroup::pair_new_members() {
  for (std::size_t m = paired_members_; m < members_.size(); ++m) {
    const std::int32_t body = members_[m];
    for (std::int32_t other : world_.lists.bodies_near(body)) {
      const MovingBody& o = world_.bodies[std::size_t(other)];
      if (o.owner == id_ && std::size_t(o.slot) < m) add_contact(body, other);
    }
    for (std::int32_t w : world_.lists.walls_near(body)) add_contact(body, -1 - w);
  }
  paired_members_ = members_.size();
}

void MovingGroup::begin(double start, const std::vector<std::int32_t>& members) {
  start_ = time_ = start;
  dimension_ = world_.geometry.dimension;
  for (std::int32_t body : members) add_member(body);
}

void MovingGroup::carry_on(std::int32_t id, double start,
                           const std::vector<std::int32_t>& members) {
  // its former members not taken by another group yet are marked, their owner kept aside
  constexpr std::int32_t kFormerMember = -3;
  std::vector<std::int32_t> former;
  former.swap(members_);
  std::vector<std::int32_t> former_owner(former.size());
  for (std::size_t m = 0; m < former.size(); ++m) {
    MovingBody& b = world_.bodies[std::size_t(former[m])];
    former_owner[m] = b.owner;
    if (b.owner < 0) b.owner = kFormerMember;
  }
  id_ = id;
  start_ = time_ = start;
  position_.clear();
  shift_.clear();
  velocity_.clear();
  // its former members first, already paired among themselves; then the new ones
  for (std::int32_t body : members)
    if (world_.bodies[std::size_t(body)].owner == kFormerMember) add_member(body);
  paired_members_ = members_.size();
  for (std::int32_t body : members)
    if (world_.bodies[std::size_t(body)].owner != id_) add_member(body);
  for (std::size_t m = 0; m < former.size(); ++m) {
    MovingBody& b = world_.bodies[std::size_t(former[m])];
    if (b.owner == kFormerMember) b.owner = former_owner[m];
  }
  // the contacts among those it keeps, as the world last committed them
  auto mine = [&](std::int32_t body) {
    return body < 0 || world_.bodies[std::size_t(body)].owner == id_;
  };
  std::erase_if(contacts_,
                [&](const Contact& c) { return !mine(c.first_body) || !mine(c.second_body); });
  for (Contact& c : contacts_) recall(c);
  last_step_ = 0.0;  // from its members' steps, as a group formed anew
}

void MovingGroup::begin_collision(double start, const std::vector<std::int32_t>& members,
                                  std::int32_t first, std::int32_t second) {
  start_ = time_ = start;
  dimension_ = world_.geometry.dimension;
  for (std::int32_t body : members) add_member(body);
  pair_new_members();
  if (second >= 0 && second < first) std::swap(first, second);
  for (Contact& c : contacts_)
    if (c.first_body == first && c.second_body == second) {
      c.loaded = true;
      c.max_compression = 0.0;
    }
}

// The integration started again at t from the members' positions and velocities there: the
// contacts of every pair of members within reach, all in the right-hand side, the bodies flying
// freely it watches, the state y = (displacements, velocities, impulses since t).
void MovingGroup::restart(double t) {
  time_ = t;
  const int d = dimension_;
  const std::size_t n = members_.size();
  origin_ = shift_;
  pair_new_members();
  watched_.clear();
  for (std::size_t m = 0; m < n; ++m)
    for (std::int32_t other : world_.lists.bodies_near(members_[m]))
      if (world_.bodies[std::size_t(other)].owner < 0)  // another group's: checked at the end
        watched_.push_back({std::int32_t(m), other});
  active_.clear();
  springs_.clear();
  springs_aside_.clear();
  spring_reach_.clear();
  spring_stiffness_.clear();
  gain_.resize(n);
  for (std::size_t m = 0; m < n; ++m)
    gain_[m] = world_.time_scale * world_.bodies[std::size_t(members_[m])].inverse_mass;
  history_changes_.clear();
  for (std::size_t i = 0; i < contacts_.size(); ++i) {
    Contact& c = contacts_[i];
    const MovingBody& first = world_.bodies[std::size_t(c.first_body)];
    c.first = first.slot;
    c.second = c.second_body < 0 ? c.second_body : world_.bodies[std::size_t(c.second_body)].slot;
    if (c.second >= 0)
      c.anchor_offset = world_.bodies[std::size_t(c.second_body)].anchor - first.anchor;
    c.slot = std::int32_t(active_.size());
    active_.push_back(std::int32_t(i));
    Spring& s = springs_.emplace_back(Spring{.first = c.first, .second = c.second});
    spring_reach_.push_back(c.reach);
    spring_stiffness_.push_back(c.law.stiffness);
    const bool hertz = c.law.effective_restitution() >= 1.0 && c.law.exponent == 1.5;
    if (!hertz || c.second < 0) {
      s.aside = std::int32_t(springs_aside_.size());
      springs_aside_.push_back({.law = c.law,
                                .max_compression = c.max_compression,
                                .spring = std::int32_t(springs_.size() - 1)});
    }
    if (c.second >= 0) {
      s.offset = c.anchor_offset + (origin_[std::size_t(c.second)] - origin_[std::size_t(c.first)]);
    } else {
      s.offset = world_.geometry.walls[std::size_t(-1 - c.second)].normal;
      springs_aside_.back().height = wall_height(c);
    }
  }
  y_.assign(2 * std::size_t(d) * n + active_.size(), 0.0);
  for (std::size_t m = 0; m < n; ++m)
    for (int k = 0; k < d; ++k)
      y_[d * (n + m) + std::size_t(k)] = world_.time_scale * velocity_[m](k);
  entries_.resize(watched_.size());
  for (std::size_t entry = 0; entry < entries_.size(); ++entry) entries_[entry] = entry;
  entries_sampled_at_ = std::nan("");
  probe_.resize(y_.size());
  peaks_.resize(springs_.size());
  for (std::size_t j = 0; j < springs_.size(); ++j) {
    const Contact& c = contacts_[std::size_t(active_[j])];
    peaks_[j] = {.max_force = c.max_force, .time_of_max = c.time_of_max_force};
  }
  if (!dense_) dense_ = std::make_unique<numerics::RungeKuttaNystrom>(world_.options.ode);
  const StepStart from = step_start();
  dense_->restart(y_, t, from.step, std::size_t(d) * n, 1.0 / world_.time_scale, from.last_error);
  fresh_ = true;
}

// After its own event, a group goes on at its own pace. At a window's start it takes the median
// of its members' last steps: a group that goes on from the last window keeps its pace, and the
// few bodies that join it from short collisions do not make it climb back from their short
// steps (the smallest of them cost the front's group four of its six steps a window: the error
// control grows a step at most fivefold). With that step goes the controller's memory of the
// group that took it, for a group formed anew as for one going on, so that the two mirror
// halves of a group that parts start alike (one went on with its memory, the other without:
// an HCP patch struck on its mirror plane parted mirror beads by 5.3e-12 of the speed at
// tolerance 1e-8).
MovingGroup::StepStart MovingGroup::step_start() const {
  if (last_step_ > 0.0) return {last_step_, dense_->last_error()};
  std::vector<std::pair<double, double>> hints;  // (step, error)
  for (std::int32_t body : members_) {
    const MovingBody& b = world_.bodies[std::size_t(body)];
    if (b.step_hint > 0.0) hints.emplace_back(b.step_hint, b.error_hint);
  }
  if (hints.empty()) return {world_.first_step, numerics::RungeKuttaNystrom::kNoLastError};
  const auto middle = hints.begin() + std::ptrdiff_t(hints.size() / 2);
  std::nth_element(hints.begin(), middle, hints.end());
  return {middle->first, middle->second};
}

void MovingGroup::member_state(std::size_t slot, const double* y, Eigen::Vector3d& x,
                               Eigen::Vector3d& v) const {
  const int d = dimension_;
  x = world_.bodies[std::size_t(members_[slot])].anchor + (origin_[slot] + read(y + d * slot, d));
  v = read(y + d * (members_.size() + slot), d) / world_.time_scale;
}

void MovingGroup::rhs(const double* y, double* dydt) {
  if (dimension_ == 3) return rhs_in<3>(y, dydt);
  rhs_in<2>(y, dydt);
}

// The right-hand side with the dimension known to the compiler: it is most of a run's time.
template <int D>
void MovingGroup::rhs_in(const double* y, double* dydt) {
  const std::size_t velocities = std::size_t(D) * members_.size();
  // in the state's units: w' = T a, q' = T F / m (x' = w / T is the Nystrom step's own)
  const double impulse_rate = world_.time_scale / world_.mass_scale;
  double* acceleration = dydt + velocities;
  double* impulse = dydt + 2 * velocities;
  std::fill(acceleration, acceleration + velocities, 0.0);
  // the springs a chunk at a time, its separations and forces on the stack (in the core's cache)
  constexpr std::size_t kChunk = 64;
  double separation[kChunk * D], squared[kChunk], force[kChunk], push[kChunk];
  const double* reach = spring_reach_.data();
  const double* stiffness = spring_stiffness_.data();
  for (std::size_t first = 0; first < springs_.size(); first += kChunk) {
    const std::size_t count = std::min(kChunk, springs_.size() - first);
    const Spring* chunk = springs_.data() + first;
    for (std::size_t j = 0; j < count; ++j) {  // the separations
      const Spring& s = chunk[j];
      if (s.second < 0) {
        squared[j] = 1.0;  // a wall's: formed below
        continue;
      }
      const double* ya = y + std::size_t(D) * std::size_t(s.first);
      const double* yb = y + std::size_t(D) * std::size_t(s.second);
      double sum = 0.0;
      for (int k = 0; k < D; ++k) {
        const double between = s.offset[k] + (yb[k] - ya[k]);
        separation[D * j + k] = between;
        sum += between * between;
      }
      squared[j] = sum;
    }
    for (std::size_t j = 0; j < count; ++j) {  // elastic Hertz, as ContactLaw::force
      const double distance = std::sqrt(squared[j]);
      const double gap = reach[first + j] - distance;
      const double overlap = gap > 0.0 ? gap : 0.0;  // std::max's reference is a branch to gcc
      force[j] = hertz_force(stiffness[first + j], overlap);
      push[j] = force[j] / distance;
    }
    for (std::size_t j = 0; j < count; ++j) {  // the accelerations, in the springs' order
      const Spring& s = chunk[j];
      double* aa = acceleration + std::size_t(D) * std::size_t(s.first);
      const double first_gain = gain_[std::size_t(s.first)];
      if (s.second >= 0) {
        if (s.aside >= 0) {  // the bi-stiffness curves
          const SpringAside& aside = springs_aside_[std::size_t(s.aside)];
          const double distance = std::sqrt(squared[j]);
          force[j] = numerics::hysteresis_force(aside.law, reach[first + j] - distance,
                                                aside.max_compression);
          push[j] = force[j] / distance;
        }
        double* ab = acceleration + std::size_t(D) * std::size_t(s.second);
        const double second_gain = gain_[std::size_t(s.second)];
        for (int k = 0; k < D; ++k) {
          aa[k] -= first_gain * push[j] * separation[D * j + k];
          ab[k] += second_gain * push[j] * separation[D * j + k];
        }
      } else {  // offset: the wall's normal; height: the origin's above the wall
        const SpringAside& aside = springs_aside_[std::size_t(s.aside)];
        const double* ya = y + std::size_t(D) * std::size_t(s.first);
        double height = aside.height;
        for (int k = 0; k < D; ++k) height += s.offset[k] * ya[k];
        force[j] =
            numerics::hysteresis_force(aside.law, reach[first + j] - height, aside.max_compression);
        if (force[j] != 0.0)
          for (int k = 0; k < D; ++k) aa[k] += first_gain * force[j] * s.offset[k];
      }
      impulse[first + j] = impulse_rate * force[j];
    }
  }
}

namespace {

// gap (m) and rate (m/s) of a sphere at xa moving at va against one at xb moving at vb, the
// two touching at distance `reach`
void sphere_gap(const Eigen::Vector3d& xa, const Eigen::Vector3d& va, const Eigen::Vector3d& xb,
                const Eigen::Vector3d& vb, double reach, double& gap, double& rate) {
  const Eigen::Vector3d between = xb - xa;
  const double distance = between.norm();
  gap = distance - reach;
  rate = between.dot(vb - va) / distance;
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
  return wall.normal.dot(bead.anchor - wall.point) + wall.normal.dot(origin_[std::size_t(c.first)]);
}

// On every elastic contact at every step: read from the state directly.
void MovingGroup::contact_gap(const Contact& c, const double* y, double& gap, double& rate) const {
  const int d = dimension_;
  const std::size_t velocities = std::size_t(d) * members_.size();
  const std::size_t a = std::size_t(d) * std::size_t(c.first);
  const double* origin_a = origin_[std::size_t(c.first)].data();
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
  const double* origin_b = origin_[std::size_t(c.second)].data();
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
  sphere_gap(
      xa, va, o.position_at(t), o.v,
      world_.geometry.radius(members_[std::size_t(w.member)]) + world_.geometry.radius(w.other),
      gap, rate);
}

// The member a watched body's entry reads, written into probe_ from the dense output at w's
// time: an event search reads that, not the whole state.
void MovingGroup::probe_entry(std::size_t entry, const numerics::RungeKuttaNystrom::Weights& w) {
  const std::size_t n = members_.size();
  const auto d = std::size_t(dimension_);
  for (std::size_t i = d * std::size_t(watched_[entry].member), end = i + d; i < end; ++i) {
    probe_[i] = dense_->component_at(w, i);
    probe_[d * n + i] = dense_->component_at(w, d * n + i);
  }
}

// At the step's end, where most are taken, the entries read the step's own state (its dense
// output there was 84 M of the event search's 191 M instructions on FCC 20^3 at tolerance
// 3e-4).
void MovingGroup::measure(double t, const std::vector<std::size_t>& entries, Samples& samples) {
  samples.gap.resize(entries.size());
  samples.rate.resize(entries.size());
  if (t == dense_->time()) {
    for (std::size_t k = 0; k < entries.size(); ++k)
      watch_gap(watched_[entries[k]], t, dense_->state().data(), samples.gap[k], samples.rate[k]);
    return;
  }
  const numerics::RungeKuttaNystrom::Weights w = dense_->weights_at(t);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    probe_entry(entries[k], w);
    watch_gap(watched_[entries[k]], t, probe_.data(), samples.gap[k], samples.rate[k]);
  }
}

// Whether entry k, its gap and rate sampled at both ends of [a, b], may reach the touch
// within: it does at an end (classify), or the cubic Hermite of its gap turns inside and
// reaches the threshold give or take the turn's depth (a dip that the cubic misses by its whole
// depth is not a dip the step resolves).
bool MovingGroup::suspect(std::size_t k, double h, const numerics::Overlaps& overlaps) const {
  const double g0 = start_samples_.gap[k], g1 = end_samples_.gap[k], r0 = start_samples_.rate[k],
               r1 = end_samples_.rate[k];
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
  if (watched_.empty()) return false;
  const numerics::OdeOptions& ode = world_.options.ode;
  const numerics::Overlaps overlaps{.join = world_.options.overlap_resolution,
                                    .leave = 0.5 * world_.options.overlap_resolution};
  // every entry at the segment's ends, its start kept from the segment before
  if (entries_sampled_at_ != a) measure(a, entries_, start_samples_);
  measure(b, entries_, end_samples_);
  suspects_.clear();
  for (std::size_t k = 0; k < entries_.size(); ++k)
    if (suspect(k, b - a, overlaps)) suspects_.push_back(entries_[k]);
  std::swap(start_samples_, end_samples_);
  entries_sampled_at_ = b;
  if (suspects_.empty()) return false;
  // the suspects searched as the compliant integrator searches: at samples_per_step cuts
  one_.gap.resize(1);
  one_.rate.resize(1);
  auto locate = [&](double t0, double t1, const Samples& s0, const Samples& s1,
                    std::vector<numerics::Crossing>& found) {
    for (std::size_t k = 0; k < suspects_.size(); ++k) {
      const std::size_t entry = suspects_[k];
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
            probe_entry(entry, dense_->weights_at(t));
            watch_gap(watched_[entry], t, probe_.data(), one_.gap[0], one_.rate[0]);
            return value(one_.gap[0], one_.rate[0]);
          },
          t0, t1, value(s0.gap[k], s0.rate[k]), value(s1.gap[k], s1.rate[k]), ode.event_tolerance);
      found.push_back({long(entry), int(crossed.kind), bracket.upper});
    }
  };
  const auto found = numerics::scan_events(
      a, b, ode.samples_per_step, ode.event_tolerance, before_, after_,
      [&](double t, Samples& s) { measure(t, suspects_, s); }, locate);
  if (found.empty()) return false;
  const auto earliest = std::min_element(
      found.begin(), found.end(), [](const auto& p, const auto& q) { return p.time < q.time; });
  event = {std::size_t(earliest->index), earliest->time};
  // every body found touching within the same cut is taken with it, one restart for the many a
  // symmetric front touches at once (taken early, a body's contact is integrated from its open
  // gap)
  taken_.clear();
  for (const auto& crossing : found) taken_.push_back(watched_[std::size_t(crossing.index)].other);
  return true;
}

// The members and active contacts at time t of the current step (their impulses folded in).
void MovingGroup::move_to(double t) {
  const int d = dimension_;
  const std::size_t n = members_.size();
  settle_histories(t);
  dense_->state_at(t, y_);
  for (std::size_t m = 0; m < n; ++m) {
    member_state(m, y_.data(), position_[m], velocity_[m]);
    shift_[m] = origin_[m] + read(y_.data() + d * m, d);
  }
  for (std::int32_t index : active_) {
    Contact& c = contacts_[std::size_t(index)];
    // its peak as track_peaks and settle_histories kept it
    c.max_force = peaks_[std::size_t(c.slot)].max_force;
    c.time_of_max_force = peaks_[std::size_t(c.slot)].time_of_max;
    c.impulse +=
        y_[2 * std::size_t(d) * n + std::size_t(c.slot)] * world_.mass_scale / world_.time_scale;
    double gap, rate;
    contact_gap(c, y_.data(), gap, rate);
    c.compression = -gap;
    c.force = numerics::hysteresis_force(c.law, -gap, c.max_compression);
    c.loaded = c.compression > 0.5 * world_.options.overlap_resolution;
    if (c.force > c.max_force) {
      c.max_force = c.force;
      c.time_of_max_force = t;
    }
  }
  time_ = t;
}

void MovingGroup::track_peaks(double t0, double t1) {
  if (t1 <= t0) return;
  const std::size_t impulses = 2 * std::size_t(dimension_) * members_.size();
  // the impulses' rates are T F / m (rhs_in)
  const double to_force = world_.mass_scale / world_.time_scale;
  for (std::size_t j = 0; j < springs_.size(); ++j) {
    Peak& p = peaks_[j];
    const auto peak = dense_->rate_peak(impulses + j, t0, t1, p.max_force / to_force);
    if (!std::isnan(peak.time)) p = {.max_force = to_force * peak.value, .time_of_max = peak.time};
  }
}

void MovingGroup::handle(const Event& event) {
  move_to(event.time);
  for (std::int32_t body : taken_)
    if (world_.bodies[std::size_t(body)].owner != id_) add_member(body);
  ++world_.stats.group_restarts;
  world_.stats.member_restarts += std::int64_t(members_.size());
  restart(time_);
}

// What the step's weights missed of the forces that switched within it, integrated along the
// cubic Hermite of their separation (onset_quadrature.hpp) and added to both ends' velocities,
// equal and opposite, and to the impulse:
// - the elastic Hertz springs between members that closed or opened (`switching`, of the
//   springs, numbered as their impulses in the state); a wall's onsets are a few beads', left;
// - every inelastic spring whose overlap turned, or crossed a corner of its curves (touch,
//   unloading's zero, loading's start at its history): its history turns with it, found here
//   and taken in as the group passes the turn (settle_histories), so that no group restarts
//   for it. Where it turned, its positions are amended too, and the next step forms its first
//   forces anew: an e = 0 contact's force drops to zero there, and the positions' error would
//   be of order h^2.
// Elsewhere only the velocities are amended: the positions' error at an onset, of order h^3.5,
// would take the step's last forces anew (they are the next step's first).
double MovingGroup::amend_switches(const State& start, const State& start_rate, State& end,
                                   const State& end_rate, double h,
                                   std::span<const std::size_t> switching) {
  using numerics::rkn43::nodes, numerics::rkn43::velocity_weights;
  const auto d = std::size_t(dimension_);
  const std::size_t velocities = d * members_.size();
  double* impulses = end.data() + 2 * velocities;
  // A spring whose whole impulse over the step, in the state's units, is under a hundredth of
  // the absolute tolerance changes its beads' velocities by less (their gains T / m are at most
  // the impulses' T / m_lightest), and its weights can miss no more: left as it is (63 % of
  // FCC 20^3's switching springs at tolerance 1e-2 and 57 % at 3e-4, 36 % of 32 x 32's at 3e-5:
  // contacts that barely load).
  const double negligible = 1e-2 * world_.options.ode.absolute_tolerance;
  for (std::size_t j : switching) {
    const Spring& s = springs_[j];
    if (s.second < 0 || s.aside >= 0 ||
        std::abs(impulses[j] - start[2 * velocities + j]) < negligible)
      continue;
    const auto a = std::size_t(s.first), b = std::size_t(s.second);
    Eigen::Vector3d r0, u0, r1, u1, unused;
    spring_separation(j, start.data(), nullptr, h, r0, u0, unused);
    spring_separation(j, end.data(), nullptr, h, r1, u1, unused);
    const numerics::OnsetQuadrature missed = numerics::hertz_onset_quadrature(
        r0, u0, r1, u1, spring_reach_[j], spring_stiffness_[j], nodes, velocity_weights);
    for (std::size_t k = 0; k < d; ++k) {
      end[velocities + d * a + k] -= gain_[a] * h * missed.impulse(k);
      end[velocities + d * b + k] += gain_[b] * h * missed.impulse(k);
    }
    impulses[j] += world_.time_scale / world_.mass_scale * h * missed.magnitude;
  }
  return amend_histories(start, start_rate, end, end_rate, h);
}

// The separation modelled by the quintic Hermite of the step's ends, whose accelerations are the
// law the step took: with the cubic, which places a turn to O(h^3) in its time, a head-on pair
// at e = 0 left 1.3e-6 of V off at tolerance 1e-6 (the quintic: 1.2e-10).
double MovingGroup::amend_histories(const State& start, const State& start_rate, State& end,
                                    const State& end_rate, double h) {
  using numerics::rkn43::nodes, numerics::rkn43::velocity_weights,
      numerics::rkn43::position_weights;
  const auto d = std::size_t(dimension_);
  const std::size_t velocities = d * members_.size();
  const double leave = 0.5 * world_.options.overlap_resolution;
  double cut = 1.0;
  history_changes_.clear();
  for (const SpringAside& aside : springs_aside_) {
    if (aside.law.effective_restitution() >= 1.0) continue;
    const auto j = std::size_t(aside.spring);
    numerics::StepSeparation model{.quintic = true};
    spring_separation(j, start.data(), start_rate.data(), h, model.r0, model.u0, model.a0);
    spring_separation(j, end.data(), end_rate.data(), h, model.r1, model.u1, model.a1);
    const double reach = spring_reach_[j], overlap0 = reach - model.r0.norm(),
                 overlap1 = reach - model.r1.norm(), history = aside.max_compression;
    const bool closing0 = model.r0.dot(model.u0) < 0.0, closing1 = model.r1.dot(model.u1) < 0.0;
    auto crosses = [&](double threshold) {
      return (overlap0 > threshold) != (overlap1 > threshold);
    };
    // smooth over the step unless its rate turns or it crosses a corner of its curves
    const double e = aside.law.restitution;
    if (closing0 == closing1 && !crosses(history * (1.0 - e * e)) &&
        !(history > 0.0 && (crosses(history) || crosses(leave))))
      continue;
    const numerics::OnsetQuadrature missed = numerics::contact_step_quadrature(
        model, reach, aside.law, history, leave, nodes, velocity_weights, position_weights);
    const bool changed = missed.change_count > 0;
    const double share = turn_cut(j, aside.law, missed, overlap1, h);
    if (share < 1.0) {
      cut = std::min(cut, share);
      continue;
    }
    const Spring& s = springs_[j];
    auto push = [&](std::size_t slot, double sign) {
      for (std::size_t k = 0; k < d; ++k) {
        end[velocities + d * slot + k] += sign * gain_[slot] * h * missed.impulse(k);
        if (changed)
          end[d * slot + k] += sign * gain_[slot] * h * h / world_.time_scale * missed.moment(k);
      }
    };
    push(std::size_t(s.first), -1.0);
    if (s.second >= 0) push(std::size_t(s.second), 1.0);
    end[2 * velocities + j] += world_.time_scale / world_.mass_scale * h * missed.magnitude;
    for (std::size_t k = 0; k < missed.change_count; ++k)
      history_changes_.push_back({.spring = std::int32_t(j),
                                  .time = dense_->time() + missed.changes[k].s * h,
                                  .overlap = missed.changes[k].history,
                                  .max_compression = missed.changes[k].history});
    // An e = 0 contact stays at its turn's overlap, at the foot of its loading curve: a rounding
    // deeper would take the loading force again, for a step the error control shortens until
    // its kick is within the tolerance. Its history lies the overlaps' resolution deeper.
    if (changed && history_changes_.back().max_compression > 0.0 &&
        aside.law.effective_restitution() == 0.0)
      history_changes_.back().max_compression += world_.options.overlap_resolution;
  }
  if (cut < 1.0) history_changes_.clear();
  return cut;
}

// After its turn a contact unloads along a curve 1 / e^2 stiffer than the loading the step took,
// and departs from the step's path; the amendment along that path errs by about
// (eta^2 / 30) F_M R^2 tau in impulse, R the path's fall after the turn over e^2 delta_p, tau
// the time after it. Where that would move the lighter body by more than the tolerance times
// the fastest speed (small e, long steps), the step is cut to end just past the turn: the share
// of h it keeps, or 1. Measured on a head-on pair, amended, against this estimate: 1.6e-3 of V
// at tolerance 1e-3 and e = 0.2 (R = 0.42, estimate 3.2e-3), 7.5e-6 at 1e-6 and e = 0.01
// (R = 0.18, 1.8e-5), 6.5e-7 at 1e-10 and e = 0.01 (R = 0.076, 2.2e-6), 2.2e-5 at 1e-3 and
// e = 0.5 (R = 0.068, 8.4e-5). A turn in the step's last 5 % is amended.
double MovingGroup::turn_cut(std::size_t j, const numerics::ContactLaw& law,
                             const numerics::OnsetQuadrature& missed, double end_overlap,
                             double h) const {
  constexpr double kCutBefore = 0.95, kPastTheTurn = 1.01;
  const auto* const last = missed.changes.begin() + missed.change_count;
  const auto* const turn = std::find_if(missed.changes.begin(), last,
                                        [](const auto& change) { return change.history > 0.0; });
  if (turn == last || turn->s >= kCutBefore) return 1.0;
  const double e = law.restitution, fall = turn->history - std::min(end_overlap, turn->history);
  // (released within the step, R > 1: the unloading lasts tau / sqrt(R), and errs by F_M times
  // that at most; at e = 0 the force drops at once, exactly as amended)
  const double ratio = fall / (e * e * turn->history),
               share = ratio <= 1.0 ? ratio * ratio : 1.0 / std::sqrt(ratio);
  const Spring& s = springs_[j];
  const double inverse_mass =  // 1 / kg, the lighter body's
      std::max(gain_[std::size_t(s.first)], s.second >= 0 ? gain_[std::size_t(s.second)] : 0.0) /
      world_.time_scale;
  const double speed_error = law.exponent * law.exponent / 30.0 * law.force(turn->history) * share *
                             (1.0 - turn->s) * h * inverse_mass;
  return speed_error <= world_.options.ode.relative_tolerance * world_.speed_bound
             ? 1.0
             : kPastTheTurn * turn->s;
}

void MovingGroup::spring_separation(std::size_t j, const double* y, const double* dydt, double h,
                                    Eigen::Vector3d& r, Eigen::Vector3d& u,
                                    Eigen::Vector3d& a) const {
  const auto d = std::size_t(dimension_);
  const std::size_t velocities = d * members_.size();
  // w = T v, w' = T x'': h w / T and h^2 w' / T
  const double to_rate = h * (1.0 / world_.time_scale), to_acceleration = h * to_rate;
  const Spring& s = springs_[j];
  const std::size_t first = d * std::size_t(s.first);
  a.setZero();
  if (s.second < 0) {  // from the bead to the wall's plane, along its normal
    double height = springs_aside_[std::size_t(s.aside)].height, speed = 0.0, pull = 0.0;
    for (std::size_t k = 0; k < d; ++k) {
      height += s.offset[k] * y[first + k];
      speed += s.offset[k] * y[velocities + first + k];
      if (dydt) pull += s.offset[k] * dydt[velocities + first + k];
    }
    r = -height * s.offset;
    u = -to_rate * speed * s.offset;
    a = -to_acceleration * pull * s.offset;
    return;
  }
  const std::size_t second = d * std::size_t(s.second);
  r = s.offset;
  u.setZero();
  for (std::size_t k = 0; k < d; ++k) {
    r(k) += y[second + k] - y[first + k];
    u(k) = to_rate * (y[velocities + second + k] - y[velocities + first + k]);
    if (dydt)
      a(k) = to_acceleration * (dydt[velocities + second + k] - dydt[velocities + first + k]);
  }
}

// J: what contact c would give back from where it is, its potential on its curve less, past
// its history on the loading curve, what its last turn booked as dissipated (settle_histories),
// so that kinetic + stored + dissipated stays the energy given, through a reloading too.
double MovingGroup::stored_energy(const Contact& c) {
  const double potential = numerics::hysteresis_energy(c.law, c.compression, c.max_compression);
  if (!(c.max_compression > 0.0) || c.compression < c.max_compression) return potential;
  const double e = c.law.restitution;
  return potential - (1.0 - e * e) * numerics::hysteresis_energy(c.law, c.max_compression, 0.0);
}

// The history changes of the step just taken up to t: where a spring turned, the unloading
// curve from its overlap there, its largest force exactly, and the energy it will not give back
// booked as dissipated, (1 - e^2) of its loading work beyond the history it had (a contact
// that reloads past its history and turns again has given back nothing between); where it
// opened, no history.
void MovingGroup::settle_histories(double t) {
  bool changed = false;
  for (const HistoryChange& change : history_changes_) {
    if (change.time > t) continue;
    const auto j = std::size_t(change.spring);
    Contact& c = contacts_[std::size_t(active_[j])];
    if (change.overlap > 0.0) {
      const double e = c.law.restitution;
      c.dissipated += (1.0 - e * e) * (numerics::hysteresis_energy(c.law, change.overlap, 0.0) -
                                       numerics::hysteresis_energy(c.law, c.max_compression, 0.0));
      const double peak = c.law.force(change.overlap);
      if (peak > peaks_[j].max_force) peaks_[j] = {.max_force = peak, .time_of_max = change.time};
    }
    c.max_compression = change.max_compression;
    springs_aside_[std::size_t(springs_[j].aside)].max_compression = change.max_compression;
    changed = true;
  }
  history_changes_.clear();
  if (changed) dense_->refresh_derivative();
}

void MovingGroup::take_step() {
  fresh_ = false;
  dense_->step(Motion{*this});
  last_step_ = dense_->last_step();
  world_.stats.member_steps += std::int64_t(members_.size());
  if (++world_.stats.steps > world_.options.max_steps)
    throw Error("moving contacts: max_steps = " + std::to_string(world_.options.max_steps) +
                " time steps taken by t = " + to_text(dense_->time()) +
                " s (compliant.max_steps in a scene); the contacts' time scale is below what the "
                "tolerance and double precision resolve");
  const auto& now = dense_->state();
  if (!std::all_of(now.begin(), now.end(), [](double x) { return std::isfinite(x); }))
    throw Error("moving contacts: the state is not finite at t = " + to_text(dense_->time()) +
                " s; speeds, forces or stiffnesses are out of the range double precision carries");
}

void MovingGroup::integrate(double end) {
  // the groups formed after this one (collisions) own bodies it may have watched as free
  restart(time_);
  while (time_ < end) {
    if (dense_->time() <= time_) {
      settle_histories(time_);
      take_step();
      continue;
    }
    const double segment_end = std::min(dense_->time(), end);
    Event event;
    const bool found = next_event(time_, segment_end, event);
    track_peaks(time_, found ? event.time : segment_end);
    if (found) {
      handle(event);
      continue;
    }
    time_ = segment_end;
  }
  if (!fresh_) move_to(end);
}

Eigen::Vector3d MovingGroup::final_position(std::int32_t slot) const {
  return position_[std::size_t(slot)];
}

void MovingGroup::commit() {
  for (std::size_t m = 0; m < members_.size(); ++m) {
    MovingBody& b = world_.bodies[std::size_t(members_[m])];
    b.x = position_[m];
    b.shift = shift_[m];
    b.v = velocity_[m];
    b.time = time_;
    b.owner = b.slot = -1;
    b.step_hint = last_step_;
    b.error_hint = dense_->last_error();
    b.last_window = world_.stats.windows;
    b.last_group = id_;
  }
  for (Contact& c : contacts_) {
    if (c.world_id < 0 && c.impulse == 0.0 && !c.loaded) continue;  // never touched
    if (c.world_id < 0) c.world_id = world_.contact_id(c.first_body, c.second_body);
    MovingContact& record = world_.contacts[std::size_t(c.world_id)];
    if (record.max_force == 0.0 && c.max_force > 0.0) ++world_.stats.contacts_loaded;
    record.joined = c.loaded;
    record.max_compression = c.max_compression;
    record.impulse = c.impulse;
    record.force = c.loaded ? c.force : 0.0;
    record.max_force = c.max_force;
    record.time_of_max_force = c.time_of_max_force;
    record.dissipated = c.dissipated;
    record.stored_energy = c.loaded ? stored_energy(c) : 0.0;
    if (c.loaded) world_.loaded_ids.push_back(c.world_id);
  }
}

void MovingGroup::release() {
  for (std::int32_t body : members_) {
    MovingBody& b = world_.bodies[std::size_t(body)];
    b.owner = b.slot = -1;
  }
}

}  // namespace mimpact::granular
