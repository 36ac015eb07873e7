#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "mimpact/kernel/non_smooth_dynamical_system.hpp"
#include "mimpact/kernel/simulation.hpp"

namespace mimpact::models {

// A steel ball dropped on a rigid steel floor under gravity; its height z is the centre's.
struct BouncingBall {
  double radius = 0.01;     // m
  double density = 7800.0;  // kg/m^3
  double young = 210e9;     // Pa, ball and floor
  double poisson = 0.3;
  double drop_height = 1.0;  // m, of the centre at rest at t = 0
  double gravity = 9.81;     // m/s^2
  double restitution = 0.8;
  // each bounce integrated in 1000 impulse steps of its own natural impulse
  double relative_delta_p = 1e-3;

  double mass() const;
  // one system (z), one interaction g = z - R with the floor
  std::shared_ptr<kernel::NonSmoothDynamicalSystem> build() const;
};

// What the ball does: the time (s), height (m) and rebound speed (m/s) of every bounce, and
// the contact forces when it first rests on the ground (the LCP's lambda, at the time of rest).
class BounceRecord : public kernel::SimulationObserver {
 public:
  void on_impact(const kernel::Simulation& simulation,
                 const kernel::ImpactReport& report) override {
    times.push_back(report.time);
    heights.push_back(simulation.system().system(0).position()(0));
    speeds.push_back(report.result.velocity(0));
  }
  kernel::EventStatus on_step(const kernel::Simulation&, const kernel::StepReport& step) override {
    if (!resting && step.contact_forces && step.contact_forces->force.size())
      resting = *step.contact_forces;
    return kernel::EventStatus::proceed();
  }
  std::vector<double> times, heights, speeds;
  std::optional<kernel::ContactForces> resting;
};

}  // namespace mimpact::models
