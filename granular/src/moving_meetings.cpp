#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "components.hpp"
#include "mimpact/granular/cell_grid.hpp"
#include "mimpact/granular/moving_contacts.hpp"
#include "moving_group.hpp"
#include "moving_world.hpp"

// The meetings of bodies flying freely (docs/design/moving_geometry.md, "Bodies in free flight,
// and groups"): when the next one falls with nothing loaded, the halo a window's groups take,
// and the groups that collisions within a window form.
namespace mimpact::granular {

namespace {

// The time in [0, horizon] at which two bodies flying freely come within `reach` of each other
// (|between + closing t| = reach), or infinity.
double meeting_time(const Eigen::Vector3d& between, const Eigen::Vector3d& relative, double reach,
                    double horizon) {
  const double b = between.dot(relative);
  if (b >= 0.0) return INFINITY;  // not approaching
  const double a = relative.squaredNorm();
  const double c = between.squaredNorm() - reach * reach;
  if (c <= 0.0) return 0.0;
  const double discriminant = b * b - a * c;
  if (discriminant < 0.0) return INFINITY;
  const double t = c / (-b + std::sqrt(discriminant));  // the smaller root, without cancellation
  return t <= horizon ? t : INFINITY;
}

// The time in [0, horizon] at which a body at x flying at v comes within `reach` of a wall's
// plane, or infinity.
double wall_meeting_time(const Plane& wall, const Eigen::Vector3d& x, const Eigen::Vector3d& v,
                         double reach, double horizon) {
  const double closing = -wall.normal.dot(v);
  if (closing <= 0.0) return INFINITY;
  const double t = std::max(0.0, (wall.normal.dot(x - wall.point) - reach) / closing);
  return t <= horizon ? t : INFINITY;
}

}  // namespace

// With nothing loaded: the earliest meeting of two bodies flying freely, or of a body and a wall,
// at the joining overlap as free_meetings finds them, or `target`. The lists see no further
// than their skin allows (a quarter of it at the fastest speed); beyond, a grid of the bodies
// where they are, its cells as wide as they may close in on each other over a horizon four times
// longer each time, finds the meeting (a 4 x 4 packing's flight of 20 s took 66 000 windows of
// the lists' horizon). A horizon whose search would visit more than kFlightCandidates per body
// ends the search there: the next call goes on from that horizon's end.
double MovingContacts::next_meeting(double target) const {
  double fastest = 0.0;
  for (std::int32_t i : moving_)
    fastest = std::max(fastest, world_->bodies[std::size_t(i)].v.norm());
  if (!(fastest > 0.0)) return target;
  double horizon = std::min(target - time_, 0.25 * world_->lists.skin() / fastest);
  double met = listed_meeting(horizon);
  while (!std::isfinite(met) && time_ + horizon < target) {
    const double longer = std::min(target - time_, kFlightHorizonGrowth * horizon);
    met = flight_meeting(longer, fastest);
    if (std::isnan(met)) return time_ + horizon;  // too many candidates: the horizon cleared
    horizon = longer;
  }
  return time_ + std::min(met, horizon);
}

// The earliest meeting within `horizon` (s, from time_) of bodies in each other's lists, or of
// a body and a wall in its list, or infinity.
double MovingContacts::listed_meeting(double horizon) const {
  const double resolution = world_->options.overlap_resolution;
  double earliest = INFINITY;
  for (std::int32_t i : moving_) {
    const MovingBody& a = world_->bodies[std::size_t(i)];
    for (std::int32_t k : world_->lists.bodies_near(i)) {
      const MovingBody& b = world_->bodies[std::size_t(k)];
      earliest = std::min(
          earliest,
          meeting_time(b.position_at(time_) - a.position_at(time_), b.v - a.v,
                       world_->geometry.radius(i) + world_->geometry.radius(k) - resolution,
                       horizon));
    }
    for (std::int32_t w : world_->lists.walls_near(i))
      earliest = std::min(
          earliest, wall_meeting_time(world_->geometry.walls[std::size_t(w)], a.position_at(time_),
                                      a.v, world_->geometry.radius(i) - resolution, horizon));
  }
  return earliest;
}

// The earliest meeting within `horizon` (s) of a moving body with any body or wall, found
// through a grid of the bodies at time_ (none moves faster than `fastest`, m/s); infinity for
// none, NaN when the search would visit more than kFlightCandidates per body.
double MovingContacts::flight_meeting(double horizon, double fastest) const {
  const BeadGeometry& geometry = world_->geometry;
  const double resolution = world_->options.overlap_resolution;
  const double largest = geometry.radius.maxCoeff(), closing = 2.0 * fastest * horizon;
  CellGrid grid(2.0 * largest + closing, geometry.dimension);
  for (std::size_t b = 0; b < world_->bodies.size(); ++b)
    grid.insert(std::int32_t(b), world_->bodies[b].position_at(time_));
  double budget = kFlightCandidates * double(world_->bodies.size()), earliest = INFINITY;
  for (std::int32_t i : moving_) {
    const MovingBody& a = world_->bodies[std::size_t(i)];
    const Eigen::Vector3d x = a.position_at(time_);
    const double radius = geometry.radius(i);
    grid.visit_near(x, radius + largest + closing, [&](std::int32_t k) {
      const MovingBody& b = world_->bodies[std::size_t(k)];
      if (k == i || (k < i && b.listed_moving)) return;
      budget -= 1.0;
      earliest =
          std::min(earliest, meeting_time(b.position_at(time_) - x, b.v - a.v,
                                          radius + geometry.radius(k) - resolution, horizon));
    });
    for (const Plane& wall : geometry.walls)
      earliest = std::min(earliest, wall_meeting_time(wall, x, a.v, radius - resolution, horizon));
    if (budget < 0.0) return NAN;
  }
  return earliest;
}

// The halo's own meetings: a body of the halo that may meet, flying freely, another body
// flying freely within twice the window (the halo's margin for a body the group speeds up)
// takes it too, and so on; as the free bodies' meetings are found (free_meetings), at the
// joining overlap. Without them a wake body of the halo, set moving by its group, touched its
// free neighbour and restarted the whole group to take it (docs/design/moving_geometry.md,
// "Bodies in free flight, and groups"). Pairs at rest or parting (touching beads ahead of a front)
// are not meetings.
void MovingContacts::link_halo_meetings(double window, std::size_t loaded_count,
                                        std::vector<std::int32_t>& linked,
                                        std::vector<std::pair<std::int32_t, std::int32_t>>& pairs) {
  const double resolution = world_->options.overlap_resolution;
  for (std::size_t l = loaded_count; l < linked.size(); ++l) {  // linked grows as bodies join
    const std::int32_t i = linked[l];
    const MovingBody& a = world_->bodies[std::size_t(i)];
    const Eigen::Vector3d x = a.position_at(time_);
    for (std::int32_t k : world_->lists.bodies_near(i)) {
      MovingBody& b = world_->bodies[std::size_t(k)];
      if (b.slot >= 0 && std::size_t(b.slot) < loaded_count) continue;  // paired by its reach
      const double t = meeting_time(
          b.position_at(time_) - x, b.v - a.v,
          world_->geometry.radius(i) + world_->geometry.radius(k) - resolution, 2.0 * window);
      if (!std::isfinite(t)) continue;
      if (b.slot < 0) {
        b.slot = std::int32_t(linked.size());
        linked.push_back(k);
      }
      pairs.emplace_back(a.slot, b.slot);
    }
  }
}

std::vector<MovingContacts::Meeting> MovingContacts::free_meetings(double end) const {
  std::vector<Meeting> meetings;
  const double horizon = end - time_;
  const double resolution = world_->options.overlap_resolution;
  for (std::int32_t i : moving_) {
    const MovingBody& a = world_->bodies[std::size_t(i)];
    if (a.owner >= 0) continue;
    const Eigen::Vector3d x = a.position_at(time_);
    for (std::int32_t k : world_->lists.bodies_near(i)) {
      const MovingBody& b = world_->bodies[std::size_t(k)];
      if (b.owner >= 0 || (k < i && b.listed_moving)) continue;
      const double t = meeting_time(
          b.position_at(time_) - x, b.v - a.v,
          world_->geometry.radius(i) + world_->geometry.radius(k) - resolution, horizon);
      if (std::isfinite(t)) meetings.push_back({time_ + t, i, k});
    }
    for (std::int32_t w : world_->lists.walls_near(i)) {
      const double t = wall_meeting_time(world_->geometry.walls[std::size_t(w)], x, a.v,
                                         world_->geometry.radius(i) - resolution, horizon);
      if (std::isfinite(t)) meetings.push_back({time_ + t, i, -1 - w});
    }
  }
  std::sort(meetings.begin(), meetings.end(),
            [](const Meeting& p, const Meeting& q) { return p.time < q.time; });
  return meetings;
}

// Bodies flying freely that meet within the window start a group at the earliest of their
// meetings, and bodies linked by meetings start one group together: a body that meets two at
// once was the first's alone, and taken by the other at a located event, which parted mirror
// beads.
void MovingContacts::form_collision_groups(const std::vector<Meeting>& meetings) {
  // the bodies that meet, numbered by slot (-1 between windows for a body flying freely)
  std::vector<std::int32_t> meeting;
  auto number = [&](std::int32_t body) {
    MovingBody& b = world_->bodies[std::size_t(body)];
    if (b.slot >= 0) return b.slot;
    b.slot = std::int32_t(meeting.size());
    meeting.push_back(body);
    return b.slot;
  };
  std::vector<std::pair<std::int32_t, std::int32_t>> pairs;
  for (const Meeting& m : meetings) {
    const std::int32_t p = number(m.first);
    pairs.emplace_back(p, m.second >= 0 ? number(m.second) : p);
  }
  Components linked(meeting.size());
  for (const auto& [p, q] : pairs) linked.join(p, q);
  std::vector<const Meeting*> earliest(meeting.size(), nullptr);
  std::vector<std::vector<std::int32_t>> members(meeting.size());
  for (const Meeting& m : meetings) {
    const std::int32_t root = linked.find(world_->bodies[std::size_t(m.first)].slot);
    if (!earliest[std::size_t(root)]) earliest[std::size_t(root)] = &m;
  }
  for (std::int32_t body : meeting)
    members[std::size_t(linked.find(world_->bodies[std::size_t(body)].slot))].push_back(body);
  for (std::int32_t body : meeting) world_->bodies[std::size_t(body)].slot = -1;
  for (std::size_t root = 0; root < meeting.size(); ++root) {
    if (members[root].empty()) continue;
    const Meeting& first = *earliest[root];
    new_group().begin_collision(first.time, members[root], first.first, first.second);
    for (std::int32_t body : members[root]) note_moving(body);
  }
}

}  // namespace mimpact::granular
