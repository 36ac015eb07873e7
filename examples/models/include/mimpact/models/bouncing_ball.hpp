#pragma once

#include <memory>

#include "mimpact/kernel/non_smooth_dynamical_system.hpp"

namespace mimpact::models {

// A steel ball dropped on a rigid steel floor under gravity; its height z is the centre's.
struct BouncingBall {
  double radius = 0.01;       // m
  double density = 7800.0;    // kg/m^3
  double young = 210e9;       // Pa, ball and floor
  double poisson = 0.3;
  double drop_height = 1.0;   // m, of the centre at rest at t = 0
  double gravity = 9.81;      // m/s^2
  double restitution = 0.8;
  // each bounce integrated in 1000 impulse steps of its own natural impulse
  double relative_delta_p = 1e-3;

  double mass() const;
  // one system (z), one interaction g = z - R with the floor
  std::shared_ptr<kernel::NonSmoothDynamicalSystem> build() const;
};

}  // namespace mimpact::models
