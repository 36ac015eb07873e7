#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "mimpact/common/fields.hpp"
#include "mimpact/granular/bead_geometry.hpp"
#include "mimpact/granular/neighbour_lists.hpp"
#include "mimpact/numerics/contact_law.hpp"
#include "mimpact/numerics/ode_options.hpp"

namespace mimpact::granular {

struct MovingContactsOptions {
  // the integration of each group: Runge-Kutta-Nystrom 4(3) to these tolerances (positions to
  // absolute_tolerance m, velocities to absolute_tolerance / T m/s and impulses to
  // absolute_tolerance m / T N s, with T the quickest contact's overlap over its closing speed
  // and m the lightest mass), events to event_tolerance s
  numerics::OdeOptions ode{.absolute_tolerance = 1e-17,
                           .relative_tolerance = 1e-10,
                           .event_tolerance = 1e-13,
                           .samples_per_step = 4};
  // m: a contact carries force once its overlap exceeds this, and until it falls below half of
  // it (a grazing contact does not join and leave at every step)
  double overlap_resolution = 1e-12;
  // m: the neighbour lists' skin; 0: a fifth of the smallest radius
  double skin = 0.0;
  std::int64_t max_steps = 10'000'000;  // time steps of all groups, before the run is abandoned

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    numerics::OdeOptions::visit_fields(self.ode, field);
    field("overlap_resolution", self.overlap_resolution, positive("m"));
    field("skin", self.skin, at_least(0.0, "m, 0 for a fifth of the smallest radius"));
    field("max_steps", self.max_steps, at_least(1));
  }
};

// One contact that has carried force: two bodies, or a body and a wall.
struct MovingContact {
  std::int32_t first = 0;
  std::int32_t second = 0;  // a body, or -1 - w for wall w
  numerics::ContactLaw law;
  bool joined = false;           // carries force now
  double max_compression = 0.0;  // m, since it last closed: where it unloads from (e < 1)
  double impulse = 0.0;          // N s, of its force over the run
  double force = 0.0;            // N, now
  double max_force = 0.0;        // N, and when (s)
  double time_of_max_force = 0.0;
  double dissipated = 0.0;     // J, lost at its turns from loading to unloading (e < 1)
  double stored_energy = 0.0;  // J, now

  bool wall() const { return second < 0; }
  // the work the bodies have done on it so far (J), the energy ledger's sign (compression
  // work positive): what it holds and what it lost
  double work() const { return stored_energy + dissipated; }
};

struct MovingContactsStats {
  std::int64_t steps = 0;             // time steps of all groups
  std::int64_t member_steps = 0;      // the bodies those steps carried
  std::int64_t windows = 0;           // synchronisation windows
  std::int64_t extended_windows = 0;  // those one group integrated beyond a window of two groups
  std::int64_t redone_groups = 0;     // groups integrated again over a window (they met another)
  std::int64_t group_restarts = 0;    // restarts of a group's integration at its own events
  std::int64_t member_restarts = 0;   // the bodies those restarts carried
  std::int64_t most_bodies_in_motion = 0;
  std::int64_t largest_group = 0;
  std::int64_t list_refreshes = 0;
  std::int64_t contacts_loaded = 0;  // contacts that have carried force
};

// The compliant contacts in the moving geometry (docs/model.md, section 17): beads and walls
// with the gaps and normals of their current positions, g = |x_k - x_i| - r_i - r_k along
// n = (x_k - x_i) / |x_k - x_i|, contacts found as they form (NeighbourLists), each with the
// law of its pair (Hertz loading, bi-stiffness unloading for e < 1, docs/model.md section 3).
//
// The cost follows what moves. A body that carries no force flies in closed form and costs
// nothing. The others are split into groups, the bodies linked by loaded contacts (and those
// close enough to meet them within a window): each group is integrated on its own by
// the Runge-Kutta-Nystrom pair RKN4(3)4FM (three forces a step: the forces depend on the
// positions alone), with its own steps. Contacts are forces of the positions and need no event:
// an inelastic one's turn to unload (its law's history) is found within the step and the step
// amended there. A group restarts only where it takes a body flying freely that it touches,
// located with dense output (TOMS 748). Groups
// meet only at the ends of short windows (at most 0.6 of the quickest contact's duration): a
// window in which two groups touched, or took the same body, is integrated again for them as one.
class MovingContacts {
 public:
  using Options = MovingContactsOptions;
  // `velocity` per body; `closed`: the contacts to report first, in order (their records are
  // contacts()[0, closed.size()), whether or not they carry force). Throws InvalidInput naming
  // an option out of range.
  MovingContacts(const BeadGeometry& geometry, std::vector<Eigen::Vector3d> velocity,
                 const std::vector<std::pair<std::int32_t, std::int32_t>>& closed,
                 MovingContactsOptions options = {});
  ~MovingContacts();

  // Advances to `target`, or until the motion ends (ended()); returns the time reached.
  double advance(double target);
  // No contact carries force and no two bodies within the lists' reach approach each other:
  // nothing will change but the flights.
  bool ended() const;
  double time() const { return time_; }
  Eigen::Vector3d position(Eigen::Index body) const;
  Eigen::Vector3d velocity(Eigen::Index body) const;
  // every contact that has carried force, and those given at construction
  const std::vector<MovingContact>& contacts() const { return contacts_; }
  // the kinetic energy of the bodies and the energy their contacts hold (J)
  double kinetic_energy() const;
  double stored_energy() const;
  const MovingContactsStats& stats() const { return stats_; }

 private:
  struct Body;
  class Group;
  friend class Group;

  // Bodies flying freely that meet within a window: when, and which (second < 0: -1 - wall).
  struct Meeting {
    double time;
    std::int32_t first, second;
  };
  // A window to `end`, or to `extended` (>= end) if one group integrates it: then no contact
  // can begin and end between two groups within it (next_windows).
  void run_window(double end, double extended);
  void refresh_lists(double end);
  void form_groups(double end);
  // form_groups' closure of its halo: bodies flying freely that its bodies meet within the
  // window, appended to `linked` (slots numbered as there) and paired
  void link_halo_meetings(double window, std::size_t loaded_count,
                          std::vector<std::int32_t>& linked,
                          std::vector<std::pair<std::int32_t, std::int32_t>>& pairs);
  // the meetings of bodies flying freely before `end`, by time
  std::vector<Meeting> free_meetings(double end) const;
  void form_collision_groups(const std::vector<Meeting>& meetings);
  bool merge_groups_that_met();
  // a group for this window, numbered in groups_
  Group& new_group();
  // The group of the window before that committed most of `members`, taken from
  // previous_groups_ (null if none is left).
  std::unique_ptr<Group> take_previous_group(const std::vector<std::int32_t>& members);
  double next_meeting(double target) const;
  // s: the lengths of the next window, and of the same window if one group integrates it
  std::pair<double, double> next_windows() const;
  void note_moving(std::int32_t body);
  // the record of the contact of the two (a body and -1 - wall), made if there is none
  std::int32_t contact_id(std::int32_t first, std::int32_t second);
  // the same, or -1 if there is none
  std::int32_t find_contact_id(std::int32_t first, std::int32_t second) const;

  const BeadGeometry& geometry_;
  MovingContactsOptions options_;
  NeighbourLists lists_;
  std::vector<Body> bodies_;
  std::vector<std::int32_t> moving_;  // bodies that have moved: the only ones whose lists move
  std::vector<MovingContact> contacts_;
  // per body: (the other body or -1 - wall, record) of its recorded contacts with later bodies
  // and walls (a bead has a dozen at most: a scan beats a hash)
  std::vector<std::vector<std::pair<std::int32_t, std::int32_t>>> contacts_of_;
  std::vector<std::int32_t> loaded_ids_;  // contacts carrying force now
  std::vector<std::unique_ptr<Group>> groups_;
  std::vector<std::unique_ptr<Group>> previous_groups_;  // the window before's, while forming
  std::vector<std::int32_t> votes_;  // per previous group: members of a component it committed
  double time_ = 0.0;
  double speed_bound_ = 0.0;      // m/s: no body moves faster (the energy is all it can have)
  double window_ = 0.0;           // s, of the next window
  double extended_window_ = 0.0;  // s, of the next window if one group integrates it
  double longest_window_ = 0.0, shortest_window_ = 0.0;  // s
  double list_bound_ = 0.0;  // s: no body leaves its list's ball within a window this long
  double first_step_ = 0.0;  // s, of a group that starts from nothing
  // The units of a group's state (docs/model.md, section 17): velocities are integrated as
  // time_scale_ v (m) and impulses as time_scale_ p / mass_scale_ (m), so that one absolute
  // tolerance weighs a position, a velocity and an impulse alike at the quickest contact's
  // scales (its overlap, closing speed and lightest mass).
  double time_scale_ = 0.0;  // s: the quickest contact's overlap / its closing speed
  double mass_scale_ = 0.0;  // kg: the lightest body
  MovingContactsStats stats_;
};

}  // namespace mimpact::granular
