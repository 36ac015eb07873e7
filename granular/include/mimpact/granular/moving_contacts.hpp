#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "mimpact/granular/bead_geometry.hpp"
#include "mimpact/granular/moving_contact.hpp"
#include "mimpact/granular/moving_contacts_options.hpp"
#include "mimpact/granular/moving_contacts_stats.hpp"
#include "mimpact/granular/progress_meter.hpp"

namespace mimpact::granular {

class MovingGroup;
struct MovingWorld;

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
  // contacts()[0, closed.size()), whether or not they carry force); `angular_velocity` per body
  // (rad/s; empty: none), the bodies solid spheres. With friction (geometry.shape.friction > 0)
  // every contact has Coulomb's law with Mindlin's tangential spring (docs/friction.md, section
  // 3, LAMMPS's conventions), and the bodies turn. Throws InvalidInput naming an option out of
  // range, or friction with restitution below 1.
  MovingContacts(const BeadGeometry& geometry, std::vector<Eigen::Vector3d> velocity,
                 const std::vector<std::pair<std::int32_t, std::int32_t>>& closed,
                 MovingContactsOptions options = {},
                 const std::vector<Eigen::Vector3d>& angular_velocity = {});
  ~MovingContacts();

  // Advances to `target`, or until the motion ends (ended()); returns the time reached.
  double advance(double target);
  // Told where the run is at each window (null: nothing).
  void set_progress(ProgressMeter* progress) { progress_ = progress; }
  // No contact carries force and no two bodies within the lists' reach approach each other:
  // nothing will change but the flights.
  bool ended() const;
  double time() const { return time_; }
  const BeadGeometry& geometry() const;
  Eigen::Vector3d position(Eigen::Index body) const;
  Eigen::Vector3d velocity(Eigen::Index body) const;
  Eigen::Vector3d angular_velocity(Eigen::Index body) const;  // rad/s
  // every contact that has carried force, and those given at construction
  const std::vector<MovingContact>& contacts() const;
  // the kinetic energy of the bodies (with their spins) and the energy their contacts hold (J)
  double kinetic_energy() const;
  double stored_energy() const;
  const MovingContactsStats& stats() const;

 private:
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
  MovingGroup& new_group();
  // The group of the window before that committed most of `members`, taken from
  // previous_groups_ (null if none is left).
  std::unique_ptr<MovingGroup> take_previous_group(const std::vector<std::int32_t>& members);
  // With nothing loaded: when the next window ends (moving_meetings.cpp)
  double next_meeting(double target) const;
  double listed_meeting(double horizon) const;
  double flight_meeting(double horizon, double fastest) const;
  static constexpr double kFlightHorizonGrowth = 4.0;
  static constexpr double kFlightCandidates = 16.0;  // pairs a free-flight search visits, per body
  // s: the lengths of the next window, and of the same window if one group integrates it
  std::pair<double, double> next_windows() const;
  // s: overlap / closing of the quickest contact that may begin within the next window, of the
  // lightest body with a neighbour in its lists at the fastest speed (a body with none begins
  // no contact while it stays within its list's ball, which the window keeps)
  double contact_time_near() const;
  // s: the longest window that quickest contact and the lists allow, and the longest that one
  // group may integrate alone
  std::pair<double, double> window_caps() const;
  void note_moving(std::int32_t body);

  // the bodies, the contacts' records, the lists and the scales its groups share
  std::unique_ptr<MovingWorld> world_;
  std::vector<std::int32_t> moving_;  // bodies that have moved: the only ones whose lists move
  std::vector<std::unique_ptr<MovingGroup>> groups_;
  std::vector<std::unique_ptr<MovingGroup>> previous_groups_;  // the window before's, while forming
  std::vector<std::int32_t> votes_;  // per previous group: members of a component it committed
  double time_ = 0.0;
  double window_ = 0.0;           // s, of the next window
  double extended_window_ = 0.0;  // s, of the next window if one group integrates it
  double shortest_window_ = 0.0;  // s
  // overlap / closing (s) of the two lightest bodies at twice the fastest speed, growing as the
  // mass^mass_exponent_ of the lighter; a contact lasts at least contact_steps_ of it
  double contact_time_ = 0.0, mass_exponent_ = 0.0, contact_steps_ = 0.0;
  std::vector<std::int32_t> by_mass_;  // the bodies, lightest first
  double list_bound_ = 0.0;  // s: no body leaves its list's ball within a window this long
  ProgressMeter* progress_ = nullptr;
};

}  // namespace mimpact::granular
