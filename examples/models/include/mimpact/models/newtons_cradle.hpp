#pragma once

#include <memory>

#include "mimpact/kernel/non_smooth_dynamical_system.hpp"

namespace mimpact::models {

// Newton's cradle: pendulums of length L hang from pivots 2R apart, so that their steel
// balls (radius R) touch at rest. Each pendulum is a LagrangianDS in its angle theta
// (M = m L^2, F_int = m g L sin theta); the contacts between neighbouring balls are
// nonlinear relations, g = |c_{i+1} - c_i| - 2R with c_i the centre of ball i. The first
// pendulum is released from theta_0 < 0 (to the left).
struct NewtonsCradle {
  int pendulums = 5;
  double length = 0.2;      // m
  double radius = 0.01;     // m
  double density = 7800.0;  // kg/m^3
  double young = 210e9;     // Pa
  double poisson = 0.3;
  double gravity = 9.81;        // m/s^2
  double release_angle = -0.3;  // rad, of the first pendulum
  double restitution = 1.0;

  double mass() const;
  double hertz_stiffness() const;
  std::shared_ptr<kernel::NonSmoothDynamicalSystem> build() const;
  // kinetic plus gravitational energy of a state of the system (J)
  double energy(const kernel::NonSmoothDynamicalSystem& system) const;
};

}  // namespace mimpact::models
