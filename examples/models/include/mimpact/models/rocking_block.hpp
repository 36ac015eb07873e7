#pragma once

#include <memory>

#include "mimpact/kernel/non_smooth_dynamical_system.hpp"

namespace mimpact::models {

// A planar rigid block (width w, height h) on a rigid floor under gravity, q = (x, y, theta) of
// its centre, contacts at its two bottom corners (body points (+/- w/2, -h/2)):
//   g_(+/-) = y +/- (w/2) sin theta - (h/2) cos theta,
// so W depends on theta. Dropped tilted, it rocks from corner to corner and comes to rest
// on both. Corner contacts are Hertz-like with the stiffness given. On a rough floor
// (friction > 0) a corner slips at s = x' + (h/2 cos theta -/+ w/2 sin theta) theta', its
// tangent row turning with the block too.
struct RockingBlock {
  double width = 0.1;         // m
  double height = 0.2;        // m
  double mass = 2.0;          // kg
  double gravity = 9.81;      // m/s^2
  double drop_height = 0.01;  // m, of the lower corner above the floor
  double tilt = 0.1;          // rad
  double stiffness = 1e9;     // N/m^1.5
  double restitution = 0.5;
  double friction = 0.0;  // Coulomb's mu at the corners; 0 a frictionless floor

  double inertia() const { return mass * (width * width + height * height) / 12.0; }
  std::shared_ptr<kernel::NonSmoothDynamicalSystem> build() const;
  double energy(const kernel::NonSmoothDynamicalSystem& system) const;
};

}  // namespace mimpact::models
