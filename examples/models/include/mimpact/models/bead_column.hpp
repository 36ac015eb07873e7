#pragma once

#include <memory>

#include "mimpact/kernel/non_smooth_dynamical_system.hpp"

namespace mimpact::models {

// A column of identical steel beads resting on a rigid floor under gravity, struck from
// above by one more bead dropped from a height. Coordinates: the heights z of the centres,
// bottom bead first, the striker last. Contact 0 is the floor's, contact i joins beads
// i - 1 and i, the last contact the striker and the top bead.
struct BeadColumn {
  int beads = 10;
  double radius = 0.01;     // m
  double density = 7800.0;  // kg/m^3
  double young = 210e9;     // Pa, beads and floor
  double poisson = 0.3;
  double gravity = 9.81;      // m/s^2
  double drop_height = 0.05;  // m, of the striker's lowest point above the column's top
  // At 0.7 the column bounces and settles within a hundred impacts; near 1 its beads
  // rattle for a long time (hundreds of thousands of impacts a second).
  double restitution = 0.7;

  double mass() const;
  std::shared_ptr<kernel::NonSmoothDynamicalSystem> build() const;
  // kinetic plus gravitational energy (J)
  double energy(const kernel::NonSmoothDynamicalSystem& system) const;
};

}  // namespace mimpact::models
