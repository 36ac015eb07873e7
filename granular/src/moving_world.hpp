#pragma once

// What the windows of the moving geometry (MovingContacts, moving_contacts.cpp) and its groups
// (MovingGroup, moving_group.hpp) share: the bodies between windows, the records of the
// contacts that have carried force, the neighbour lists and the scales of the integration.

#include <Eigen/Dense>
#include <cstdint>
#include <utility>
#include <vector>

#include "mimpact/granular/bead_geometry.hpp"
#include "mimpact/granular/moving_contact.hpp"
#include "mimpact/granular/moving_contacts_options.hpp"
#include "mimpact/granular/moving_contacts_stats.hpp"
#include "mimpact/granular/neighbour_lists.hpp"

namespace mimpact::granular {

// A body between windows: where it is and how it moves.
struct MovingBody {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();  // m, at `time`
  // m: where it began, and x less that, carried on its own: a gap is formed from the anchors'
  // difference and the shifts', not from coordinates rounded to the packing's size at every
  // window (which set a floor of 1e-12 of the speed on a 10-bead line's velocities)
  Eigen::Vector3d anchor = Eigen::Vector3d::Zero(), shift = Eigen::Vector3d::Zero();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();      // m/s
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();  // rad/s (about z in the plane): kept in flight
  double time = 0.0;                                // s; flying freely, it is at x + v (t - time)
  double inverse_mass = 0.0;
  std::int32_t owner = -1;  // the group integrating it in this window, or -1: flying freely
  std::int32_t slot = -1;   // its place among its group's members
  // s: the last step its group took, and its controller's memory (the error ratio of that
  // step), where the next group starts
  double step_hint = 0.0, error_hint = 0.0;
  // the group that committed it, and in which window: the group of the window before that
  // committed most of a new group's members goes on as that group (MovingGroup::carry_on)
  std::int64_t last_window = -1;
  std::int32_t last_group = -1;
  bool listed_moving = false;  // among the bodies that have moved (MovingContacts::moving_)

  Eigen::Vector3d position_at(double t) const { return x + v * (t - time); }
  Eigen::Vector3d shift_at(double t) const { return shift + v * (t - time); }
};

struct MovingWorld {
  // Throws InvalidInput naming an option of `asked` out of range.
  MovingWorld(const BeadGeometry& beads, const MovingContactsOptions& asked);

  // the record of the contact of the two (a body and -1 - wall), made if there is none
  std::int32_t contact_id(std::int32_t first, std::int32_t second);
  // the same, or -1 if there is none
  std::int32_t find_contact_id(std::int32_t first, std::int32_t second) const;
  // Throws BudgetSpent at time t (s) when the steps and windows taken exceed options.max_steps,
  // or the body steps options.max_body_steps: every loop of a run counts against its budget.
  void check_budgets(double t) const;

  const BeadGeometry& geometry;
  MovingContactsOptions options;
  NeighbourLists lists;
  std::vector<MovingBody> bodies;
  std::vector<MovingContact> contacts;  // every contact that has carried force, and the closed
  // per body: (the other body or -1 - wall, record) of its recorded contacts with later bodies
  // and walls (a bead has a dozen at most: a scan beats a hash)
  std::vector<std::vector<std::pair<std::int32_t, std::int32_t>>> contacts_of;
  std::vector<std::int32_t> loaded_ids;  // contacts carrying force now
  double speed_bound = 0.0;  // m/s: no body moves faster (the energy is all it can have)
  // some contact has friction: the groups integrate spins and Mindlin springs (MovingGroup)
  bool rough = false;
  double first_step = 0.0;  // s, of a group that starts from nothing
  // The units of a group's state (docs/design/moving_geometry.md): velocities are integrated as
  // time_scale v (m) and impulses as time_scale p / mass_scale (m), so that one absolute
  // tolerance weighs a position, a velocity and an impulse alike at the quickest contact's
  // scales (its overlap, closing speed and lightest mass).
  double time_scale = 0.0;  // s: the quickest contact's overlap / its closing speed
  double mass_scale = 0.0;  // kg: the lightest body
  MovingContactsStats stats;
};

}  // namespace mimpact::granular
