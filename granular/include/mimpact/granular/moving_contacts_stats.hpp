#pragma once

#include <cstdint>

namespace mimpact::granular {

// The work counters of the moving geometry (moving_contacts.hpp).
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
  std::int64_t amended_springs = 0;  // rough planar springs amended at a switch within a step
};

}  // namespace mimpact::granular
