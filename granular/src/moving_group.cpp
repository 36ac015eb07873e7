#include "moving_group.hpp"

#include <algorithm>
#include <cmath>

#include "mimpact/common/error.hpp"
#include "mimpact/numerics/internal/event_scan.hpp"
#include "mimpact/numerics/internal/root_bracketing.hpp"

// One group's integration over a window: M x'' = sum of its loaded contacts' forces along the
// current normals, Dormand-Prince 5(4) on (displacements from the last restart, velocities,
// impulses), restarted where one of its contacts joins, leaves or turns (docs/model.md,
// section 17).
namespace mimpact::granular {

using plugins::internal::ContactEvent;

namespace {

Eigen::Vector3d read(const double* y, int dimension) {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int k = 0; k < dimension; ++k) x(k) = y[k];
  return x;
}

void add(double* y, const Eigen::Vector3d& x, int dimension) {
  for (int k = 0; k < dimension; ++k) y[k] += x(k);
}

}  // namespace

void MovingContacts::Group::add_member(std::int32_t body) {
  Body& b = world_.bodies_[std::size_t(body)];
  b.owner = id_;
  b.slot = std::int32_t(members_.size());
  members_.push_back(body);
  position_.push_back(b.position_at(time_));
  velocity_.push_back(b.v);
  partners_.emplace_back();
}

std::int32_t MovingContacts::Group::find_contact(std::int32_t first_body,
                                                 std::int32_t second_body) {
  if (second_body >= 0 && second_body < first_body) std::swap(first_body, second_body);
  const std::uint64_t key = contact_key(first_body, second_body);
  const auto found = local_ids_.find(key);
  if (found != local_ids_.end()) return found->second;
  Contact c;
  const auto known = world_.contact_ids_.find(key);
  if (known != world_.contact_ids_.end()) {
    c.world_id = known->second;
    const MovingContact& record = world_.contacts_[std::size_t(c.world_id)];
    c.law = record.law;
    c.max_compression = record.max_compression;
    c.impulse = record.impulse;
    c.max_force = record.max_force;
    c.time_of_max_force = record.time_of_max_force;
    c.dissipated = record.dissipated;
  } else {
    c.law = second_body >= 0 ? world_.geometry_.bead_law(first_body, second_body)
                             : world_.geometry_.wall_law(first_body, std::size_t(-1 - second_body));
  }
  c.first_body = first_body;
  c.second_body = second_body;
  const Eigen::VectorXd& radius = world_.geometry_.radius;
  c.reach = radius(first_body) + (second_body >= 0 ? radius(second_body) : 0.0);
  const std::int32_t index = std::int32_t(contacts_.size());
  contacts_.push_back(c);
  local_ids_.emplace(key, index);
  return index;
}

void MovingContacts::Group::begin(double start, const std::vector<std::int32_t>& members,
                                  const std::vector<std::int32_t>& loaded) {
  start_ = time_ = start;
  dimension_ = world_.geometry_.dimension;
  for (std::int32_t body : members) add_member(body);
  for (std::int32_t id : loaded) {
    const MovingContact& record = world_.contacts_[std::size_t(id)];
    contacts_[std::size_t(find_contact(record.first, record.second))].loaded = true;
  }
  restart(start);
}

void MovingContacts::Group::begin_collision(double start, std::int32_t first, std::int32_t second) {
  start_ = time_ = start;
  dimension_ = world_.geometry_.dimension;
  add_member(first);
  if (second >= 0) add_member(second);
  Contact& c = contacts_[std::size_t(find_contact(first, second))];
  c.loaded = true;
  c.max_compression = 0.0;
  restart(start);
}

// The integration started again at t from the members' positions and velocities there: slots,
// the pairs watched, the state y = (displacements, velocities, impulses since t).
void MovingContacts::Group::restart(double t) {
  time_ = t;
  const int d = dimension_;
  const std::size_t n = members_.size();
  origin_ = position_;
  loaded_.clear();
  for (auto& partners : partners_) partners.clear();
  for (std::size_t i = 0; i < contacts_.size(); ++i) {
    Contact& c = contacts_[i];
    if (!c.loaded) continue;
    c.first = world_.bodies_[std::size_t(c.first_body)].slot;
    c.second = c.second_body < 0 ? c.second_body : world_.bodies_[std::size_t(c.second_body)].slot;
    c.slot = std::int32_t(loaded_.size());
    loaded_.push_back(std::int32_t(i));
    partners_[std::size_t(c.first)].push_back(c.second_body);
    if (c.second >= 0) partners_[std::size_t(c.second)].push_back(c.first_body);
  }
  y_.assign(2 * std::size_t(d) * n + loaded_.size(), 0.0);
  for (std::size_t m = 0; m < n; ++m)
    for (int k = 0; k < d; ++k) y_[d * (n + m) + std::size_t(k)] = velocity_[m](k);
  watched_.clear();
  for (std::size_t m = 0; m < n; ++m) {
    const std::int32_t body = members_[m];
    const auto& partners = partners_[m];
    const auto loaded_with = [&](std::int32_t other) {
      return std::find(partners.begin(), partners.end(), other) != partners.end();
    };
    for (std::int32_t other : world_.lists_.bodies_near(body)) {
      const Body& o = world_.bodies_[std::size_t(other)];
      if (o.owner == id_ ? std::size_t(o.slot) < m : o.owner >= 0) continue;  // once; not theirs
      if (!loaded_with(other)) watched_.push_back({std::int32_t(m), other});
    }
    for (std::int32_t w : world_.lists_.walls_near(body))
      if (!loaded_with(-1 - w)) watched_.push_back({std::int32_t(m), -1 - w});
  }
  for (Samples* s : {&before_, &after_}) {
    s->gap.resize(watched_.size() + loaded_.size());
    s->rate.resize(s->gap.size());
  }
  probe_ = y_;
  double first_step = last_step_ > 0.0 ? last_step_ : world_.first_step_;
  for (std::int32_t body : members_)
    if (world_.bodies_[std::size_t(body)].step_hint > 0.0)
      first_step = std::min(first_step, world_.bodies_[std::size_t(body)].step_hint);
  if (!dense_) dense_ = std::make_unique<numerics::internal::DenseOutput>(world_.options_.ode);
  dense_->restart(y_, t, first_step);
  fresh_ = true;
}

void MovingContacts::Group::rhs(const double* y, double* dydt) {
  const int d = dimension_;
  const std::size_t n = members_.size();
  const std::size_t velocities = std::size_t(d) * n;
  std::copy(y + velocities, y + 2 * velocities, dydt);
  std::fill(dydt + velocities, dydt + 2 * velocities, 0.0);
  for (std::int32_t index : loaded_) {
    const Contact& c = contacts_[std::size_t(index)];
    const std::size_t a = std::size_t(c.first);
    const Eigen::Vector3d xa = origin_[a] + read(y + d * a, d);
    const Body& body_a = world_.bodies_[std::size_t(c.first_body)];
    double force;
    if (c.second >= 0) {
      const std::size_t b = std::size_t(c.second);
      const Eigen::Vector3d between = origin_[b] + read(y + d * b, d) - xa;
      const double distance = between.norm();
      force = numerics::hysteresis_force(c.law, c.reach - distance, c.max_compression);
      if (force != 0.0) {
        const Eigen::Vector3d push = (force / distance) * between;
        add(dydt + velocities + d * a, -body_a.inverse_mass * push, d);
        add(dydt + velocities + d * b,
            world_.bodies_[std::size_t(c.second_body)].inverse_mass * push, d);
      }
    } else {
      const Plane& wall = world_.geometry_.walls[std::size_t(-1 - c.second)];
      force = numerics::hysteresis_force(c.law, c.reach - wall.normal.dot(xa - wall.point),
                                         c.max_compression);
      if (force != 0.0)
        add(dydt + velocities + d * a, body_a.inverse_mass * force * wall.normal, d);
    }
    dydt[2 * velocities + std::size_t(c.slot)] = force;
  }
}

void MovingContacts::Group::contact_gap(const Contact& c, const double* y, double& gap,
                                        double& rate) const {
  const int d = dimension_;
  const std::size_t n = members_.size();
  const std::size_t a = std::size_t(c.first);
  const Eigen::Vector3d xa = origin_[a] + read(y + d * a, d);
  const Eigen::Vector3d va = read(y + d * (n + a), d);
  if (c.second >= 0) {
    const std::size_t b = std::size_t(c.second);
    const Eigen::Vector3d between = origin_[b] + read(y + d * b, d) - xa;
    const double distance = between.norm();
    gap = distance - c.reach;
    rate = between.dot(read(y + d * (n + b), d) - va) / distance;
  } else {
    const Plane& wall = world_.geometry_.walls[std::size_t(-1 - c.second)];
    gap = wall.normal.dot(xa - wall.point) - c.reach;
    rate = wall.normal.dot(va);
  }
}

void MovingContacts::Group::watch_gap(const Watch& w, double t, const double* y, double& gap,
                                      double& rate) const {
  const int d = dimension_;
  const std::size_t n = members_.size();
  const std::size_t a = std::size_t(w.member);
  const Eigen::Vector3d xa = origin_[a] + read(y + d * a, d);
  const Eigen::Vector3d va = read(y + d * (n + a), d);
  const double ra = world_.geometry_.radius(members_[a]);
  if (w.other < 0) {
    const Plane& wall = world_.geometry_.walls[std::size_t(-1 - w.other)];
    gap = wall.normal.dot(xa - wall.point) - ra;
    rate = wall.normal.dot(va);
    return;
  }
  const Body& o = world_.bodies_[std::size_t(w.other)];
  Eigen::Vector3d xb, vb;
  if (o.owner == id_) {
    xb = origin_[std::size_t(o.slot)] + read(y + d * std::size_t(o.slot), d);
    vb = read(y + d * (n + std::size_t(o.slot)), d);
  } else {  // flying freely
    xb = o.position_at(t);
    vb = o.v;
  }
  const Eigen::Vector3d between = xb - xa;
  const double distance = between.norm();
  gap = distance - ra - world_.geometry_.radius(w.other);
  rate = between.dot(vb - va) / distance;
}

void MovingContacts::Group::measure(double t, Samples& samples) {
  dense_->state_at(t, probe_);
  for (std::size_t i = 0; i < watched_.size(); ++i)
    watch_gap(watched_[i], t, probe_.data(), samples.gap[i], samples.rate[i]);
  for (std::size_t i = 0; i < loaded_.size(); ++i)
    contact_gap(contacts_[std::size_t(loaded_[i])], probe_.data(), samples.gap[watched_.size() + i],
                samples.rate[watched_.size() + i]);
}

// The earliest event of a watched pair or loaded contact in [a, b] of the current step, as the
// compliant integrator finds its own (plugins::internal::classify, TOMS 748).
bool MovingContacts::Group::next_event(double a, double b, Event& event) {
  const numerics::OdeOptions& ode = world_.options_.ode;
  const plugins::internal::Overlaps overlaps{.join = world_.options_.overlap_resolution,
                                             .leave = 0.5 * world_.options_.overlap_resolution};
  one_.gap.resize(1);
  one_.rate.resize(1);
  auto value_at = [&](std::size_t entry, double t) {
    dense_->state_at(t, probe_);
    if (entry < watched_.size())
      watch_gap(watched_[entry], t, probe_.data(), one_.gap[0], one_.rate[0]);
    else
      contact_gap(contacts_[std::size_t(loaded_[entry - watched_.size()])], probe_.data(),
                  one_.gap[0], one_.rate[0]);
  };
  auto locate = [&](double t0, double t1, const Samples& s0, const Samples& s1,
                    std::vector<numerics::internal::Crossing>& found) {
    for (std::size_t entry = 0; entry < s0.gap.size(); ++entry) {
      const plugins::internal::ContactWatch watch{.joined = entry >= watched_.size(),
                                                  .gap_before = s0.gap[entry],
                                                  .gap_after = s1.gap[entry],
                                                  .rate_before = s0.rate[entry],
                                                  .rate_after = s1.rate[entry]};
      const plugins::internal::Classified crossed = plugins::internal::classify(watch, overlaps);
      if (crossed.kind == ContactEvent::none) continue;
      if (crossed.at_start) {
        if (entry != last_event_ || t0 > a) found.push_back({long(entry), int(crossed.kind), t0});
        continue;
      }
      auto value = [&](double gap, double rate) {
        return plugins::internal::event_function(crossed.kind, gap, rate, overlaps);
      };
      const numerics::Bracket bracket = numerics::narrow_crossing(
          [&](double t) {
            value_at(entry, t);
            return value(one_.gap[0], one_.rate[0]);
          },
          t0, t1, value(watch.gap_before, watch.rate_before),
          value(watch.gap_after, watch.rate_after), ode.event_tolerance);
      if (entry == last_event_ && bracket.upper <= a + ode.event_tolerance) continue;
      found.push_back({long(entry), int(crossed.kind), bracket.upper});
    }
  };
  const auto found = numerics::internal::scan_events(
      a, b, ode.samples_per_step, ode.event_tolerance, before_, after_,
      [&](double t, Samples& s) { measure(t, s); }, locate);
  if (found.empty()) return false;
  const auto earliest = std::min_element(
      found.begin(), found.end(), [](const auto& p, const auto& q) { return p.time < q.time; });
  event = {std::size_t(earliest->index), ContactEvent(earliest->kind), earliest->time};
  return true;
}

// The members and loaded contacts at time t of the current step (their impulses folded in).
void MovingContacts::Group::move_to(double t) {
  const int d = dimension_;
  const std::size_t n = members_.size();
  dense_->state_at(t, y_);
  for (std::size_t m = 0; m < n; ++m) {
    position_[m] = origin_[m] + read(&y_[d * m], d);
    velocity_[m] = read(&y_[d * (n + m)], d);
  }
  for (std::int32_t index : loaded_) {
    Contact& c = contacts_[std::size_t(index)];
    c.impulse += y_[2 * std::size_t(d) * n + std::size_t(c.slot)];
    double gap, rate;
    contact_gap(c, y_.data(), gap, rate);
    c.compression = -gap;
    c.force = numerics::hysteresis_force(c.law, -gap, c.max_compression);
    if (c.force > c.max_force) {
      c.max_force = c.force;
      c.time_of_max_force = t;
    }
  }
  time_ = t;
}

void MovingContacts::Group::handle(const Event& event) {
  move_to(event.time);
  last_event_ = event.entry;
  if (event.entry < watched_.size()) {  // joining: a new member, perhaps, and a loaded contact
    const Watch w = watched_[event.entry];
    if (w.other >= 0 && world_.bodies_[std::size_t(w.other)].owner != id_) {
      if (world_.bodies_[std::size_t(w.other)].owner >= 0)
        throw Error("moving contacts: a group took a body of another (internal error)");
      add_member(w.other);
    }
    Contact& c = contacts_[std::size_t(find_contact(members_[std::size_t(w.member)], w.other))];
    c.loaded = true;
    c.max_compression = 0.0;
    // the entry of the new contact, which the restart puts last among the loaded
    last_event_ = std::size_t(-1);
  } else {
    Contact& c = contacts_[std::size_t(loaded_[event.entry - watched_.size()])];
    if (event.kind == ContactEvent::leaving) {
      c.loaded = false;
      c.max_compression = 0.0;  // a contact that opens forgets its history
      c.force = 0.0;
      last_event_ = std::size_t(-1);
    } else if (c.compression > c.max_compression) {  // turning, from its loading curve
      const double e = c.law.restitution;
      c.dissipated += (1.0 - e * e) * numerics::hysteresis_energy(c.law, c.compression, 0.0);
      c.max_compression = c.compression;
    }
  }
  ++world_.stats_.group_restarts;
  restart(time_);
}

void MovingContacts::Group::take_step() {
  fresh_ = false;
  dense_->step([this](const numerics::internal::DenseOutput::State& y,
                      numerics::internal::DenseOutput::State& dydt,
                      double) { rhs(y.data(), dydt.data()); });
  last_step_ = dense_->last_step();
  if (++world_.stats_.steps > world_.options_.max_steps)
    throw Error("moving contacts: max_steps = " + std::to_string(world_.options_.max_steps) +
                " time steps taken by t = " + to_text(dense_->time()) +
                " s (compliant.max_steps in a scene); the contacts' time scale is below what the "
                "tolerance and double precision resolve");
  const auto& now = dense_->state();
  if (!std::all_of(now.begin(), now.end(), [](double x) { return std::isfinite(x); }))
    throw Error("moving contacts: the state is not finite at t = " + to_text(dense_->time()) +
                " s; speeds, forces or stiffnesses are out of the range double precision carries");
}

void MovingContacts::Group::integrate(double end) {
  // the groups formed after this one (collisions) own bodies it may have watched as free
  restart(time_);
  while (time_ < end) {
    if (dense_->time() <= time_) {
      take_step();
      continue;
    }
    const double segment_end = std::min(dense_->time(), end);
    Event event;
    if (next_event(time_, segment_end, event)) {
      handle(event);
      continue;
    }
    time_ = segment_end;
    last_event_ = std::size_t(-1);
  }
  if (!fresh_) move_to(end);
}

Eigen::Vector3d MovingContacts::Group::final_position(std::int32_t slot) const {
  return position_[std::size_t(slot)];
}

void MovingContacts::Group::commit() {
  for (std::size_t m = 0; m < members_.size(); ++m) {
    Body& b = world_.bodies_[std::size_t(members_[m])];
    b.x = position_[m];
    b.v = velocity_[m];
    b.time = time_;
    b.owner = b.slot = -1;
    b.step_hint = last_step_;
  }
  for (const Contact& c : contacts_) {
    const std::int32_t id =
        c.world_id >= 0 ? c.world_id : world_.contact_id(c.first_body, c.second_body);
    MovingContact& record = world_.contacts_[std::size_t(id)];
    record.joined = c.loaded;
    record.max_compression = c.max_compression;
    record.impulse = c.impulse;
    record.force = c.loaded ? c.force : 0.0;
    record.max_force = c.max_force;
    record.time_of_max_force = c.time_of_max_force;
    record.dissipated = c.dissipated;
    record.stored_energy =
        c.loaded ? numerics::hysteresis_energy(c.law, c.compression, c.max_compression) : 0.0;
    if (c.loaded) world_.loaded_ids_.push_back(id);
  }
}

void MovingContacts::Group::release() {
  for (std::int32_t body : members_) {
    Body& b = world_.bodies_[std::size_t(body)];
    b.owner = b.slot = -1;
  }
}

}  // namespace mimpact::granular
