#include "moving_group.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "mimpact/common/error.hpp"

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

}  // namespace

void MovingGroup::add_member(std::int32_t body) {
  MovingBody& b = world_.bodies[std::size_t(body)];
  b.owner = id_;
  b.slot = std::int32_t(members_.size());
  members_.push_back(body);
  state_.position.push_back(b.position_at(time_));
  state_.shift.push_back(b.shift_at(time_));
  state_.velocity.push_back(b.v);
  state_.spin.push_back(b.omega);
}

void MovingGroup::recall(Contact& c) const {
  const MovingContact* record =
      c.world_id >= 0 ? &world_.contacts[std::size_t(c.world_id)] : nullptr;
  c.loaded = record && record->joined;
  if (record) {
    static_cast<ContactState&>(c) = *record;
  } else {
    const numerics::ContactLaw law = c.law;
    static_cast<ContactState&>(c) = {.law = law};
  }
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
  state_.position.clear();
  state_.shift.clear();
  state_.velocity.clear();
  state_.spin.clear();
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
  state_.origin = state_.shift;
  pair_new_members();
  search_.watched.clear();
  for (std::size_t m = 0; m < n; ++m)
    for (std::int32_t other : world_.lists.bodies_near(members_[m]))
      if (world_.bodies[std::size_t(other)].owner < 0)  // another group's: checked at the end
        search_.watched.push_back({std::int32_t(m), other});
  springs_.active.clear();
  springs_.list.clear();
  springs_.aside.clear();
  springs_.reach.clear();
  springs_.stiffness.clear();
  state_.gain.resize(n);
  for (std::size_t m = 0; m < n; ++m)
    state_.gain[m] = world_.time_scale * world_.bodies[std::size_t(members_[m])].inverse_mass;
  springs_.history_changes.clear();
  for (std::size_t i = 0; i < contacts_.size(); ++i) {
    Contact& c = contacts_[i];
    const MovingBody& first = world_.bodies[std::size_t(c.first_body)];
    c.first = first.slot;
    c.second = c.second_body < 0 ? c.second_body : world_.bodies[std::size_t(c.second_body)].slot;
    if (c.second >= 0)
      c.anchor_offset = world_.bodies[std::size_t(c.second_body)].anchor - first.anchor;
    c.slot = std::int32_t(springs_.active.size());
    springs_.active.push_back(std::int32_t(i));
    Spring& s = springs_.list.emplace_back(Spring{.first = c.first, .second = c.second});
    springs_.reach.push_back(c.reach);
    springs_.stiffness.push_back(c.law.stiffness);
    const bool hertz = c.law.effective_restitution() >= 1.0 && c.law.exponent == 1.5;
    if (!hertz || c.second < 0) {
      s.aside = std::int32_t(springs_.aside.size());
      springs_.aside.push_back(
          {.contact = std::int32_t(i), .spring = std::int32_t(springs_.list.size() - 1)});
    }
    if (c.second >= 0) {
      s.offset = c.anchor_offset +
                 (state_.origin[std::size_t(c.second)] - state_.origin[std::size_t(c.first)]);
    } else {
      s.offset = world_.geometry.walls[std::size_t(-1 - c.second)].normal;
      springs_.aside.back().height = wall_height(c);
    }
  }
  y_.assign(2 * std::size_t(d) * n + springs_.active.size(), 0.0);
  for (std::size_t m = 0; m < n; ++m)
    for (int k = 0; k < d; ++k)
      y_[d * (n + m) + std::size_t(k)] = world_.time_scale * state_.velocity[m](k);
  search_.entries.resize(search_.watched.size());
  for (std::size_t entry = 0; entry < search_.entries.size(); ++entry)
    search_.entries[entry] = entry;
  search_.sampled_at = std::nan("");
  probe_.resize(y_.size());
  springs_.peaks.resize(springs_.list.size());
  for (std::size_t j = 0; j < springs_.list.size(); ++j) {
    const Contact& c = contacts_[std::size_t(springs_.active[j])];
    springs_.peaks[j] = {.max_force = c.max_force, .time_of_max = c.time_of_max_force};
  }
  const StepStart from = step_start();
  if (world_.rough) {
    restart_rough();
    if (!rough_) rough_ = std::make_unique<numerics::DenseOutput>(world_.options.ode);
    probe_.resize(y_.size());
    rough_->restart(y_, t, from.step);
  } else {
    if (!dense_) dense_ = std::make_unique<numerics::RungeKuttaNystrom>(world_.options.ode);
    dense_->restart(y_, t, from.step, std::size_t(d) * n, 1.0 / world_.time_scale, from.last_error);
  }
  fresh_ = true;
}

// After its own event, a group goes on at its own pace. At a window's start it takes the median
// of its members' last steps: a group that goes on from the last window keeps its pace, and the
// few bodies that join it from short collisions do not make it climb back from their short
// steps (the error control grows a step at most fivefold). With that step goes the controller's
// memory of the group that took it, for a group formed anew as for one going on, so that the two
// mirror halves of a group that parts start alike (docs/design/moving_geometry.md, "Round-off
// and symmetry").
MovingGroup::StepStart MovingGroup::step_start() const {
  if (last_step_ > 0.0)
    return {last_step_, dense_ ? dense_->last_error() : numerics::RungeKuttaNystrom::kNoLastError};
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
  x = world_.bodies[std::size_t(members_[slot])].anchor +
      (state_.origin[slot] + read(y + d * slot, d));
  v = read(y + d * (members_.size() + slot), d) / world_.time_scale;
}

void MovingGroup::rhs(const double* y, double* dydt) {
  if (world_.rough) {
    if (dimension_ == 3) return rhs_spatial_rough(y, dydt);
    return rhs_planar_rough(y, dydt);
  }
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
  const double* reach = springs_.reach.data();
  const double* stiffness = springs_.stiffness.data();
  for (std::size_t first = 0; first < springs_.list.size(); first += kChunk) {
    const std::size_t count = std::min(kChunk, springs_.list.size() - first);
    const Spring* chunk = springs_.list.data() + first;
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
      force[j] = numerics::hertz_force(stiffness[first + j], overlap);
      push[j] = force[j] / distance;
    }
    for (std::size_t j = 0; j < count; ++j) {  // the accelerations, in the springs' order
      const Spring& s = chunk[j];
      double* aa = acceleration + std::size_t(D) * std::size_t(s.first);
      const double first_gain = state_.gain[std::size_t(s.first)];
      if (s.second >= 0) {
        if (s.aside >= 0) {  // the bi-stiffness curves
          const ContactState& c =
              contacts_[std::size_t(springs_.aside[std::size_t(s.aside)].contact)];
          const double distance = std::sqrt(squared[j]);
          force[j] =
              numerics::hysteresis_force(c.law, reach[first + j] - distance, c.max_compression);
          push[j] = force[j] / distance;
        }
        double* ab = acceleration + std::size_t(D) * std::size_t(s.second);
        const double second_gain = state_.gain[std::size_t(s.second)];
        for (int k = 0; k < D; ++k) {
          aa[k] -= first_gain * push[j] * separation[D * j + k];
          ab[k] += second_gain * push[j] * separation[D * j + k];
        }
      } else {  // offset: the wall's normal; height: the origin's above the wall
        const SpringAside& aside = springs_.aside[std::size_t(s.aside)];
        const ContactState& c = contacts_[std::size_t(aside.contact)];
        const double* ya = y + std::size_t(D) * std::size_t(s.first);
        double height = aside.height;
        for (int k = 0; k < D; ++k) height += s.offset[k] * ya[k];
        force[j] = numerics::hysteresis_force(c.law, reach[first + j] - height, c.max_compression);
        if (force[j] != 0.0)
          for (int k = 0; k < D; ++k) aa[k] += first_gain * force[j] * s.offset[k];
      }
      impulse[first + j] = impulse_rate * force[j];
    }
  }
}

// The members and active contacts at time t of the current step (their impulses folded in).
void MovingGroup::move_to(double t) {
  const int d = dimension_;
  const std::size_t n = members_.size();
  settle_histories(t);
  if (rough_) {
    if (t >= rough_->time()) {
      y_ = rough_->state();  // amended
    } else {
      rough_->state_at(t, y_);
      const double start = rough_->time() - rough_->last_step();
      amend_rough((t - start) / rough_->last_step(), y_);
    }
    move_rough();
  } else {
    dense_->state_at(t, y_);
  }
  for (std::size_t m = 0; m < n; ++m) {
    member_state(m, y_.data(), state_.position[m], state_.velocity[m]);
    state_.shift[m] = state_.origin[m] + read(y_.data() + d * m, d);
  }
  for (std::int32_t index : springs_.active) {
    Contact& c = contacts_[std::size_t(index)];
    // its peak as track_peaks and settle_histories kept it
    c.max_force = springs_.peaks[std::size_t(c.slot)].max_force;
    c.time_of_max_force = springs_.peaks[std::size_t(c.slot)].time_of_max;
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
  if (t1 <= t0 || rough_) return;  // with friction: the peaks of the segments' ends (move_to)
  const std::size_t impulses = 2 * std::size_t(dimension_) * members_.size();
  // the impulses' rates are T F / m (rhs_in)
  const double to_force = world_.mass_scale / world_.time_scale;
  for (std::size_t j = 0; j < springs_.list.size(); ++j) {
    Peak& p = springs_.peaks[j];
    const auto peak = dense_->rate_peak(impulses + j, t0, t1, p.max_force / to_force);
    if (!std::isnan(peak.time)) p = {.max_force = to_force * peak.value, .time_of_max = peak.time};
  }
}

void MovingGroup::handle(const Event& event) {
  move_to(event.time);
  for (std::int32_t body : search_.taken)
    if (world_.bodies[std::size_t(body)].owner != id_) add_member(body);
  ++world_.stats.group_restarts;
  world_.stats.member_restarts += std::int64_t(members_.size());
  restart(time_);
}

void MovingGroup::take_step() {
  fresh_ = false;
  if (rough_) {
    rough_->step(RoughMotion{*this});
    last_step_ = rough_->last_step();
    amend_rough_step();
  } else {
    dense_->step(Motion{*this});
    last_step_ = dense_->last_step();
  }
  world_.stats.member_steps += std::int64_t(members_.size());
  ++world_.stats.steps;
  world_.check_budgets(stepper_time());
  const auto& now = stepper_state();
  if (!std::all_of(now.begin(), now.end(), [](double x) { return std::isfinite(x); }))
    throw Error("moving contacts: the state is not finite at t = " + to_text(stepper_time()) +
                " s; speeds, forces or stiffnesses are out of the range double precision carries");
}

void MovingGroup::integrate(double end) {
  // the groups formed after this one (collisions) own bodies it may have watched as free
  restart(time_);
  while (time_ < end) {
    if (stepper_time() <= time_) {
      settle_histories(time_);
      take_step();
      continue;
    }
    const double segment_end = std::min(stepper_time(), end);
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
  return state_.position[std::size_t(slot)];
}

void MovingGroup::commit() {
  for (std::size_t m = 0; m < members_.size(); ++m) {
    MovingBody& b = world_.bodies[std::size_t(members_[m])];
    b.x = state_.position[m];
    b.shift = state_.shift[m];
    b.v = state_.velocity[m];
    b.omega = state_.spin[m];
    b.time = time_;
    b.owner = b.slot = -1;
    b.step_hint = last_step_;
    b.error_hint = dense_ ? dense_->last_error() : numerics::RungeKuttaNystrom::kNoLastError;
    b.last_window = world_.stats.windows;
    b.last_group = id_;
  }
  for (Contact& c : contacts_) {
    if (c.world_id < 0 && c.impulse == 0.0 && !c.loaded) continue;  // never touched
    if (c.world_id < 0) c.world_id = world_.contact_id(c.first_body, c.second_body);
    MovingContact& record = world_.contacts[std::size_t(c.world_id)];
    if (record.max_force == 0.0 && c.max_force > 0.0) ++world_.stats.contacts_loaded;
    static_cast<ContactState&>(record) = c;
    record.joined = c.loaded;
    if (!c.loaded) {
      record.force = 0.0;
      record.stretch.setZero();  // it opened: its spring forgets
    }
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
