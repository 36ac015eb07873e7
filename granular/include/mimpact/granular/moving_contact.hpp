#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "mimpact/numerics/contact_law.hpp"

namespace mimpact::granular {

// What a contact carries from one window to the next and reports, wherever it is held (the
// world's record, MovingContact, or a group's working copy while it integrates the contact): its
// law, its histories (the normal one, its largest overlap since it closed; with friction its
// Mindlin spring's stretch) and its record over the run. One definition, copied whole between
// the two.
struct ContactState {
  numerics::ContactLaw law;
  double max_compression = 0.0;  // m, since it last closed: where it unloads from (e < 1)
  double impulse = 0.0;          // N s, of its force over the run
  double force = 0.0;            // N, now
  double max_force = 0.0;        // N, and when (s)
  double time_of_max_force = 0.0;
  double dissipated = 0.0;  // J, lost at its turns from loading to unloading (e < 1)
  // with friction: its tangential spring's stretch (m, in the world's frame, perpendicular to
  // the normal from its first body to its second, 0 while open) and its tangential impulse on
  // the second (N s)
  Eigen::Vector3d stretch = Eigen::Vector3d::Zero();
  Eigen::Vector3d tangential_impulse = Eigen::Vector3d::Zero();
  double slip_work = 0.0;  // J, the tangential force's work against the slip (beside work())
};

// One contact that has carried force: two bodies, or a body and a wall.
struct MovingContact : ContactState {
  std::int32_t first = 0;
  std::int32_t second = 0;     // a body, or -1 - w for wall w
  bool joined = false;         // carries force now
  double stored_energy = 0.0;  // J, now

  bool wall() const { return second < 0; }
  // the work the bodies have done on it so far (J), the energy ledger's sign (compression
  // work positive): what it holds and what it lost
  double work() const { return stored_energy + dissipated; }
};

}  // namespace mimpact::granular
