#include "mimpact/granular/moving_contacts.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>

#include "components.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/granular/contact_model.hpp"
#include "moving_group.hpp"
#include "moving_world.hpp"

// The windows of the moving-geometry integration (docs/design/moving_geometry.md): groups formed
// from the loaded contacts, collisions of bodies flying freely, the groups integrated each on
// its own, checked against each other at the window's end, merged and integrated again where
// they met, then committed.
namespace mimpact::granular {

MovingContacts::MovingContacts(const BeadGeometry& geometry, std::vector<Eigen::Vector3d> velocity,
                               const std::vector<std::pair<std::int32_t, std::int32_t>>& closed,
                               MovingContactsOptions options,
                               const std::vector<Eigen::Vector3d>& angular_velocity)
    : world_(std::make_unique<MovingWorld>(geometry, options)) {
  world_->rough = geometry.rough();
  if (world_->rough && geometry.shape.effective_restitution() < 1.0)
    throw InvalidInput(invalid_value_message(
        "contact.restitution", geometry.shape.restitution,
        "1 with friction in the moving geometry, whose Mindlin springs are integrated for "
        "elastic contacts"));
  double energy = 0.0;
  for (std::size_t b = 0; b < world_->bodies.size(); ++b) {
    MovingBody& body = world_->bodies[b];
    body.x = body.anchor = geometry.position[b];
    body.v = velocity[b];
    if (!angular_velocity.empty()) body.omega = angular_velocity[b];
    body.inverse_mass = 1.0 / geometry.mass(Eigen::Index(b));
    energy += 0.5 * geometry.mass(Eigen::Index(b)) *
              (velocity[b].squaredNorm() +
               0.4 * std::pow(geometry.radius(Eigen::Index(b)), 2) * body.omega.squaredNorm());
    if (velocity[b].squaredNorm() > 0.0 || body.omega.squaredNorm() > 0.0)
      note_moving(std::int32_t(b));
  }
  for (const auto& [first, second] : closed) world_->contact_id(first, second);
  world_->speed_bound = std::sqrt(2.0 * energy / geometry.mass.minCoeff());
  // the quickest contact: the stiffest pair of the lightest bodies at twice the fastest speed,
  // unloading at once if any law is inelastic
  double stiffness = 0.0;
  bool elastic = true;
  auto note_law = [&](const numerics::ContactLaw& law) {
    stiffness = std::max(stiffness, law.stiffness);
    elastic = elastic && law.effective_restitution() >= 1.0;
  };
  for (Eigen::Index b = 0; b < geometry.body_count(); ++b) {
    note_law(geometry.bead_law(b, b));
    for (std::size_t w = 0; w < geometry.walls.size(); ++w) note_law(geometry.wall_law(b, w));
  }
  const double eta = geometry.shape.exponent, closing = 2.0 * world_->speed_bound;
  const double overlap = std::pow(
      (1.0 + eta) * 0.5 * geometry.mass.minCoeff() * closing * closing / (2.0 * 2.0 * stiffness),
      1.0 / (1.0 + eta));
  // `overlap` is 2^(-1/(1+eta)) of the pair's largest (its energy halved), and a Hertz contact
  // lasts 2.94 largest overlaps / closing speed: 3.9 overlap / closing; an inelastic one at
  // least its loading half, 1.95. A window of at most 0.6 of the quickest contact (2.34 or 1.17
  // overlap / closing) ends before a contact begun between two groups within it has ended, so
  // that the groups find it (merge_groups_that_met); and no body leaves its list's ball within
  // it. A window lasts about eight steps of its largest group, within [0.5 overlap / closing,
  // that bound], or longer where one group integrates it (next_windows)
  list_bound_ = 0.25 * world_->lists.skin() / world_->speed_bound;
  contact_time_ = overlap / closing;
  contact_steps_ = elastic ? 3.9 : 1.95;
  mass_exponent_ = 1.0 / (1.0 + eta);
  shortest_window_ = std::min(0.5 * contact_time_, list_bound_);
  by_mass_.resize(world_->bodies.size());
  std::iota(by_mass_.begin(), by_mass_.end(), 0);
  std::stable_sort(by_mass_.begin(), by_mass_.end(), [&](std::int32_t a, std::int32_t b) {
    return geometry.mass(a) < geometry.mass(b);
  });
  window_ = extended_window_ = shortest_window_;
  // the gaps are differences of coordinates: their rounding must leave the overlaps digits
  double largest_coordinate = 0.0;
  for (const Eigen::Vector3d& x : geometry.position)
    largest_coordinate = std::max(largest_coordinate, x.cwiseAbs().maxCoeff());
  for (const Plane& wall : geometry.walls)
    largest_coordinate = std::max(largest_coordinate, wall.point.cwiseAbs().maxCoeff());
  check_overlap_resolved(overlap, largest_coordinate, faster_strikers_advice(true));
  world_->first_step = 1e-3 * overlap / closing;
  world_->time_scale = overlap / closing;
  world_->mass_scale = geometry.mass.minCoeff();
}

MovingContacts::~MovingContacts() = default;

const std::vector<MovingContact>& MovingContacts::contacts() const { return world_->contacts; }

const MovingContactsStats& MovingContacts::stats() const { return world_->stats; }

const BeadGeometry& MovingContacts::geometry() const { return world_->geometry; }

Eigen::Vector3d MovingContacts::position(Eigen::Index body) const {
  return world_->bodies[std::size_t(body)].position_at(time_);
}
Eigen::Vector3d MovingContacts::velocity(Eigen::Index body) const {
  return world_->bodies[std::size_t(body)].v;
}

Eigen::Vector3d MovingContacts::angular_velocity(Eigen::Index body) const {
  return world_->bodies[std::size_t(body)].omega;
}

double MovingContacts::kinetic_energy() const {
  double energy = 0.0;
  for (std::size_t k = 0; k < world_->bodies.size(); ++k) {
    const MovingBody& b = world_->bodies[k];
    const double r = world_->geometry.radius(Eigen::Index(k));
    energy += 0.5 * (b.v.squaredNorm() + 0.4 * r * r * b.omega.squaredNorm()) / b.inverse_mass;
  }
  return energy;
}

double MovingContacts::stored_energy() const {
  double energy = 0.0;
  for (std::int32_t id : world_->loaded_ids)
    energy += world_->contacts[std::size_t(id)].stored_energy;
  return energy;
}

bool MovingContacts::ended() const {
  if (!world_->loaded_ids.empty()) return false;
  for (std::int32_t i : moving_) {
    const MovingBody& a = world_->bodies[std::size_t(i)];
    const Eigen::Vector3d x = a.position_at(time_);
    for (std::int32_t k : world_->lists.bodies_near(i)) {
      const MovingBody& b = world_->bodies[std::size_t(k)];
      if ((b.position_at(time_) - x).dot(b.v - a.v) < 0.0) return false;
    }
    for (std::int32_t w : world_->lists.walls_near(i))
      if (world_->geometry.walls[std::size_t(w)].normal.dot(a.v) < 0.0) return false;
  }
  return true;
}

double MovingContacts::advance(double target) {
  while (time_ < target && !ended()) {
    double end = std::min(target, time_ + window_);
    double extended = std::min(target, time_ + extended_window_);
    // with nothing loaded, the bodies fly to a short window before the next meeting, which finds
    // it with any other meeting of the same instant (a mirror pair's, a rounding later)
    if (world_->loaded_ids.empty())
      end = extended = std::min(target, std::max(end, next_meeting(target) - shortest_window_));
    if (!(end > time_))
      throw Error("moving contacts: a window of " + to_text(window_) +
                  " s no longer moves t = " + to_text(time_) +
                  " s in double precision; the contacts' time scale is below what the run's "
                  "length resolves (check the speeds and stiffnesses, or end_time)");
    run_window(end, extended);
    std::tie(window_, extended_window_) = next_windows();
    if (progress_)
      progress_->report({.time = time_,
                         .steps = world_->stats.steps,
                         .contacts = std::int64_t(world_->loaded_ids.size())});
    world_->check_budgets(time_);  // a window is a loop of the run too
  }
  return time_;
}

// A window restarts its groups and makes them take every body that may meet them within it:
// long windows restart less, short ones keep the groups small. A window of eight steps of the
// largest group, within [0.5 overlap / closing, 0.6 of the quickest contact], does both: 0.5
// restarted the FCC front's group at every step at tolerance 1e-4. (Four steps, as with
// Dormand-Prince's steps of six forces, made the Nystrom steps of three restart twice as often:
// FCC 20^3 at 1e-3 took 49 windows in 0.81 s, 28 in 0.57 s with eight. A third of the quickest
// contact rather than 0.6 made a 32 x 32 packing's windows of its wake's many groups five steps
// of its largest: at tolerance 3e-5, 117 windows and 435 k body steps, 1.207 G instructions
// (callgrind, the whole command) against 82, 421 k and 1.081 G, at RMS errors 1.11e-6 and
// 1.05e-6.)
// Where one group integrated the last window, the next may take its steps up to 3 overlap /
// closing: no two groups can meet within it if it keeps one (run_window). An FCC 20^3
// packing's front group, stepping 6 us at tolerance 1e-4, took two steps a window of 8 us (0.84
// s; 0.52 s with these). Longer still, the front outran the halo formed at the window's start,
// and each body it touched restarted the whole group (36 in one window of 24 us; twelve or
// sixteen steps a window doubled FCC 20^3's body steps at 3e-4, with 511 and 954 restarts).
std::pair<double, double> MovingContacts::next_windows() const {
  constexpr double kWindowSteps = 8.0;
  const MovingGroup* largest = nullptr;
  int count = 0;
  for (const auto& group : groups_)
    if (group) {
      ++count;
      if (!largest || group->members().size() > largest->members().size()) largest = group.get();
    }
  if (!largest) return {shortest_window_, shortest_window_};  // a group that starts steps short
  const double steps = kWindowSteps * largest->last_step();
  const auto [longest, longest_alone] = window_caps();
  const double window = std::clamp(steps, shortest_window_, longest);
  return {window, count == 1 ? std::clamp(steps, shortest_window_, longest_alone) : window};
}

std::pair<double, double> MovingContacts::window_caps() const {
  const double contact_time = contact_time_near();
  return {std::min(0.6 * (contact_steps_ * contact_time), list_bound_),
          std::min(3.0 * contact_time, list_bound_)};
}

double MovingContacts::contact_time_near() const {
  const NeighbourLists& lists = world_->lists;
  const Eigen::VectorXd& mass = world_->geometry.mass;
  for (std::int32_t b : by_mass_)
    if (!lists.bodies_near(b).empty() || !lists.walls_near(b).empty())
      return contact_time_ * std::pow(mass(b) / mass(by_mass_.front()), mass_exponent_);
  return std::numeric_limits<double>::infinity();
}

MovingGroup& MovingContacts::new_group() {
  groups_.push_back(std::make_unique<MovingGroup>(*world_, std::int32_t(groups_.size())));
  return *groups_.back();
}

std::unique_ptr<MovingGroup> MovingContacts::take_previous_group(
    const std::vector<std::int32_t>& members) {
  // votes_ is all zeros between calls: only the groups voted for are counted and reset
  votes_.resize(previous_groups_.size(), 0);
  std::int32_t best = -1;
  std::vector<std::int32_t> voted;
  for (std::int32_t body : members) {
    const MovingBody& b = world_->bodies[std::size_t(body)];
    if (b.last_window != world_->stats.windows - 1 || !previous_groups_[std::size_t(b.last_group)])
      continue;
    if (votes_[std::size_t(b.last_group)]++ == 0) voted.push_back(b.last_group);
    if (best < 0 || votes_[std::size_t(b.last_group)] > votes_[std::size_t(best)])
      best = b.last_group;
  }
  for (std::int32_t g : voted) votes_[std::size_t(g)] = 0;
  if (best < 0) return nullptr;
  return std::move(previous_groups_[std::size_t(best)]);
}

void MovingContacts::run_window(double end, double extended) {
  refresh_lists(extended);
  if (!world_->loaded_ids.empty()) {  // a light body the lists now bring near shortens it
    const auto [longest, longest_alone] = window_caps();
    end = std::min(end, time_ + longest);
    extended = std::max(end, std::min(extended, time_ + longest_alone));
  }
  previous_groups_ = std::move(groups_);
  groups_.clear();
  form_groups(extended);  // groups formed for a longer window only take more bodies
  previous_groups_.clear();
  std::vector<Meeting> meetings = free_meetings(extended);
  const auto count =
      std::count_if(groups_.begin(), groups_.end(), [](const auto& g) { return bool(g); });
  if (count == 1 && meetings.empty()) {
    if (extended > end) ++world_->stats.extended_windows;
    end = extended;
  } else {
    std::erase_if(meetings, [&](const Meeting& m) { return m.time > end; });
  }
  form_collision_groups(meetings);
  std::vector<bool> integrated;
  while (true) {
    integrated.resize(groups_.size(), false);
    for (std::size_t g = 0; g < groups_.size(); ++g)
      if (groups_[g] && !integrated[g]) {
        groups_[g]->integrate(end);
        integrated[g] = true;
      }
    if (!merge_groups_that_met()) break;
  }
  world_->loaded_ids.clear();
  std::int64_t in_motion = 0;
  for (const auto& group : groups_) {
    if (!group) continue;
    in_motion += std::int64_t(group->members().size());
    world_->stats.largest_group =
        std::max(world_->stats.largest_group, std::int64_t(group->members().size()));
    for (std::int32_t body : group->members()) note_moving(body);
    group->commit();
  }
  world_->stats.most_bodies_in_motion = std::max(world_->stats.most_bodies_in_motion, in_motion);
  time_ = end;
  ++world_->stats.windows;
}

void MovingContacts::note_moving(std::int32_t body) {
  MovingBody& b = world_->bodies[std::size_t(body)];
  if (b.listed_moving) return;
  b.listed_moving = true;
  moving_.push_back(body);
}

// Bodies that may leave their list's ball before `end` make their lists again now.
void MovingContacts::refresh_lists(double end) {
  const double half_skin = 0.5 * world_->lists.skin();
  for (std::int32_t i : moving_) {
    const MovingBody& b = world_->bodies[std::size_t(i)];
    const Eigen::Vector3d x = b.position_at(time_);
    const double speed = std::max(b.v.norm(), world_->speed_bound);
    if ((x - world_->lists.anchor(i)).norm() + speed * (end - time_) > half_skin)
      world_->lists.refresh(i, x);
  }
  world_->stats.list_refreshes = world_->lists.refreshes();
}

// The groups at the window's start: the bodies linked by loaded contacts, those close enough
// to meet within the window, and the halo: bodies flying freely (at rest, ahead of a front)
// that a group's body may touch within the window join it from the start, so that the group
// does not restart to take them. A body of the halo of two groups links them: taken by the
// first alone, it made the partition, and so the steps, depend on the bodies' numbering, and a
// mirror strike asymmetric to the tolerance.
void MovingContacts::form_groups(double end) {
  if (world_->loaded_ids.empty()) return;
  // each body once (slot, -1 between windows, marks it: its index in `linked`), in memory order
  std::vector<std::int32_t> linked;
  auto note = [&](std::int32_t body) {
    if (world_->bodies[std::size_t(body)].slot != -1) return;
    world_->bodies[std::size_t(body)].slot = 0;
    linked.push_back(body);
  };
  for (std::int32_t id : world_->loaded_ids) {
    const MovingContact& c = world_->contacts[std::size_t(id)];
    note(c.first);
    if (!c.wall()) note(c.second);
  }
  std::sort(linked.begin(), linked.end());
  const std::size_t loaded_count = linked.size();
  for (std::size_t i = 0; i < loaded_count; ++i)
    world_->bodies[std::size_t(linked[i])].slot = std::int32_t(i);
  // the pairs that may meet within the window: two loaded bodies, or a loaded one and a body of
  // its halo (numbered after the loaded ones as it is found)
  const double window = end - time_;
  std::vector<std::pair<std::int32_t, std::int32_t>> pairs;
  for (std::size_t l = 0; l < loaded_count; ++l) {
    const std::int32_t i = linked[l];
    const MovingBody& a = world_->bodies[std::size_t(i)];
    const double speed = a.v.norm();
    for (std::int32_t k : world_->lists.bodies_near(i)) {
      MovingBody& b = world_->bodies[std::size_t(k)];
      const bool loaded = b.slot >= 0 && std::size_t(b.slot) < loaded_count;
      if (loaded && k < i) continue;  // the pair once
      // apart by more than the radii and the reach: compared squared, a square root less a pair
      const double reach = 2.0 * (speed + b.v.norm()) * window;
      const double apart = world_->geometry.radius(i) + world_->geometry.radius(k) +
                           (loaded ? reach : reach + world_->options.overlap_resolution);
      if ((b.position_at(time_) - a.x).squaredNorm() >= apart * apart) continue;
      if (!loaded && b.slot < 0) {
        b.slot = std::int32_t(linked.size());
        linked.push_back(k);
      }
      pairs.emplace_back(a.slot, b.slot);
    }
  }
  link_halo_meetings(window, loaded_count, linked, pairs);
  for (std::int32_t id : world_->loaded_ids) {
    const MovingContact& c = world_->contacts[std::size_t(id)];
    if (!c.wall())
      pairs.emplace_back(world_->bodies[std::size_t(c.first)].slot,
                         world_->bodies[std::size_t(c.second)].slot);
  }
  Components components(linked.size());
  for (const auto& [p, q] : pairs) components.join(p, q);
  std::vector<std::vector<std::int32_t>> members(linked.size());
  for (std::int32_t i : linked)
    members[std::size_t(components.find(world_->bodies[std::size_t(i)].slot))].push_back(i);
  for (std::int32_t i : linked) world_->bodies[std::size_t(i)].slot = -1;
  // The largest groups choose first which group of the last window they go on as (the one most
  // of their bodies came from), so that a front's group keeps its contacts: chosen in the
  // components' order, a few bodies parted from it took it first, and the front's group of the
  // 100 x 100 packing paired its 20 000 contacts anew in most windows (2.3 M contacts made at
  // tolerance 1e-4, a fifth of the run's time; 73 k now, and the run 1.82 s -> 1.20 s).
  std::vector<std::size_t> by_size(members.size());
  for (std::size_t c = 0; c < members.size(); ++c) by_size[c] = c;
  std::stable_sort(by_size.begin(), by_size.end(), [&](std::size_t p, std::size_t q) {
    return members[p].size() > members[q].size();
  });
  std::vector<std::unique_ptr<MovingGroup>> carried(members.size());
  for (std::size_t c : by_size)
    if (!members[c].empty()) carried[c] = take_previous_group(members[c]);
  for (std::size_t c = 0; c < members.size(); ++c) {
    if (members[c].empty()) continue;
    if (carried[c]) {
      groups_.push_back(std::move(carried[c]));
      groups_.back()->carry_on(std::int32_t(groups_.size() - 1), time_, members[c]);
    } else {
      new_group().begin(time_, members[c]);
    }
  }
}

// Groups whose bodies overlap at the window's end met during it: each set that met is
// integrated again from the earliest start as one group. True when some did.
bool MovingContacts::merge_groups_that_met() {
  Components met(groups_.size());
  bool any = false;
  const double resolution = world_->options.overlap_resolution;
  for (const auto& group : groups_) {
    if (!group) continue;
    const auto& members = group->members();
    for (std::size_t m = 0; m < members.size(); ++m) {
      const std::int32_t i = members[m];
      const Eigen::Vector3d x = group->final_position(std::int32_t(m));
      for (std::int32_t k : world_->lists.bodies_near(i)) {
        const MovingBody& b = world_->bodies[std::size_t(k)];
        if (b.owner < 0 || b.owner == group->id()) continue;
        const double gap = (groups_[std::size_t(b.owner)]->final_position(b.slot) - x).norm() -
                           world_->geometry.radius(i) - world_->geometry.radius(k);
        if (gap < -resolution) {
          met.join(group->id(), b.owner);
          any = true;
        }
      }
    }
  }
  if (!any) return false;
  std::vector<std::vector<std::int32_t>> sets(groups_.size());
  for (const auto& group : groups_)
    if (group) sets[std::size_t(met.find(group->id()))].push_back(group->id());
  for (const auto& set : sets) {
    if (set.size() < 2) continue;
    // the largest goes on with the others' members, integrated again from the earliest start
    const std::int32_t largest = *std::max_element(set.begin(), set.end(), [&](auto a, auto b) {
      return groups_[std::size_t(a)]->members().size() < groups_[std::size_t(b)]->members().size();
    });
    double start = INFINITY;
    std::vector<std::int32_t> members;
    for (std::int32_t g : set) {
      start = std::min(start, groups_[std::size_t(g)]->start());
      const auto& mine = groups_[std::size_t(g)]->members();
      members.insert(members.end(), mine.begin(), mine.end());
      groups_[std::size_t(g)]->release();
    }
    std::unique_ptr<MovingGroup> merged = std::move(groups_[std::size_t(largest)]);
    for (std::int32_t g : set) groups_[std::size_t(g)].reset();
    world_->stats.redone_groups += std::int64_t(set.size());
    groups_.push_back(std::move(merged));
    groups_.back()->carry_on(std::int32_t(groups_.size() - 1), start, members);
  }
  return true;
}

}  // namespace mimpact::granular
