// Example e: a rigid block rocking on two corners of a frictionless floor, a contact
// Jacobian that turns with the block. Impacts at one corner give u+ = -e u- there, the
// horizontal velocity never changes, energy falls at impacts and is kept in flight, and
// the block comes to rest on both corners, each carrying half its weight.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "mimpact/models/rocking_block.hpp"
#include "mimpact/models/simulation_setup.hpp"

namespace mimpact::models {
namespace {

struct Rocking : kernel::SimulationObserver {
  const RockingBlock* block = nullptr;
  void on_impact(const kernel::Simulation& simulation,
                 const kernel::ImpactReport& report) override {
    const double energy = block->energy(simulation.system());
    impacts.push_back(report);
    energies_after.push_back(energy);
    horizontal.push_back(simulation.system().system(0).velocity()(0));
  }
  kernel::EventStatus on_step(const kernel::Simulation& simulation,
                              const kernel::StepReport& step) override {
    energies_at_steps.push_back({step.time, block->energy(simulation.system()), step.event});
    if (step.contact_forces) forces = *step.contact_forces;
    return kernel::EventStatus::proceed();
  }
  struct Sample {
    double time, energy;
    bool event;
  };
  std::vector<kernel::ImpactReport> impacts;
  std::vector<double> energies_after, horizontal;
  std::vector<Sample> energies_at_steps;
  std::optional<kernel::ContactForces> forces;
};

TEST(RockingBlock, RocksLosesEnergyAndRestsOnBothCorners) {
  const RockingBlock block;
  SimulationSetup setup;
  setup.impacts.relative_delta_p = 1e-3;
  auto system = block.build();
  const double start_energy = block.energy(*system);
  kernel::Simulation simulation = make_simulation(system, setup);
  Rocking rocking;
  rocking.block = &block;
  simulation.add_observer(rocking);
  simulation.run(0.0, 2.0);

  ASSERT_GE(rocking.impacts.size(), 5u);
  double previous = start_energy;
  for (std::size_t k = 0; k < rocking.impacts.size(); ++k) {
    const kernel::ImpactReport& impact = rocking.impacts[k];
    if (impact.interactions.size() == 1) {
      EXPECT_NEAR(impact.result.velocity(0), -block.restitution * impact.velocity_before(0),
                  1e-9 * std::abs(impact.velocity_before(0)))
          << "impact " << k;
    }
    EXPECT_EQ(rocking.horizontal[k], 0.0);  // frictionless: no horizontal impulse
    EXPECT_LT(rocking.energies_after[k], previous) << "impact " << k;
    previous = rocking.energies_after[k];
  }
  // between impacts the energy is kept to the ODE tolerance
  for (std::size_t k = 1; k < rocking.energies_at_steps.size(); ++k) {
    const auto& a = rocking.energies_at_steps[k - 1];
    const auto& b = rocking.energies_at_steps[k];
    if (!b.event) {
      EXPECT_NEAR(b.energy, a.energy, 1e-7 * start_energy) << "step " << k;
    }
  }

  const Eigen::VectorXd& q = system->system(0).position();
  EXPECT_NEAR(q(2), 0.0, 1e-6);
  EXPECT_NEAR(q(1), block.height / 2, 1e-8);
  EXPECT_EQ(system->index_sets().persistent.size(), 2u);
  ASSERT_TRUE(rocking.forces);
  ASSERT_EQ(rocking.forces->force.size(), 2);
  const double half_weight = block.mass * block.gravity / 2;
  EXPECT_NEAR(rocking.forces->force(0), half_weight, 1e-6 * half_weight);
  EXPECT_NEAR(rocking.forces->force(1), half_weight, 1e-6 * half_weight);
}

// The block's pivot phase, integrated on its own: standing on corner `side` (body point
// (side w/2, -h/2)) that stays on the floor, q = (x, theta) and their rates; the corner's normal
// force N and friction F from the Newton-Euler equations with the corner's vertical
// acceleration 0 and, sticking, its horizontal one 0, or, slipping (direction `sliding`, the
// sign of the contact point's velocity), F = -mu N sliding. Classical Runge-Kutta at dt.
struct Pivot {
  const RockingBlock& block;
  double side, mu;
  double sliding = 0.0;  // 0: sticks

  // (x, theta, x', theta') -> its rate, and the slip of the corner (m/s) and the forces
  Eigen::Vector4d rate(const Eigen::Vector4d& z, double* slip = nullptr,
                       Eigen::Vector2d* forces = nullptr) const {
    const double a = block.width / 2, b = block.height / 2, m = block.mass;
    const double theta = z(1), omega = z(3);
    const double rx = side * a * std::cos(theta) + b * std::sin(theta);
    const double ry = side * a * std::sin(theta) - b * std::cos(theta);
    // unknowns (x'', y'', theta'', N, F)
    Eigen::Matrix<double, 5, 5> A = Eigen::Matrix<double, 5, 5>::Zero();
    Eigen::Matrix<double, 5, 1> rhs = Eigen::Matrix<double, 5, 1>::Zero();
    A(0, 0) = m, A(0, 4) = -1.0;
    A(1, 1) = m, A(1, 3) = -1.0, rhs(1) = -m * block.gravity;
    A(2, 2) = block.inertia(), A(2, 3) = -rx, A(2, 4) = ry;
    A(3, 1) = 1.0, A(3, 2) = rx, rhs(3) = omega * omega * ry;
    if (sliding == 0.0) {
      A(4, 0) = 1.0, A(4, 2) = -ry, rhs(4) = omega * omega * rx;
    } else {
      A(4, 4) = 1.0, A(4, 3) = mu * sliding;
    }
    const Eigen::Matrix<double, 5, 1> u = A.fullPivLu().solve(rhs);
    if (slip) *slip = z(2) - omega * ry;
    if (forces) *forces = {u(3), u(4)};
    return {z(2), z(3), u(0), u(2)};
  }
  Eigen::Vector4d run(Eigen::Vector4d z, double end, double dt) const {
    for (double t = 0.0; t < end - 0.5 * dt; t += dt) {
      const Eigen::Vector4d k1 = rate(z), k2 = rate(z + 0.5 * dt * k1),
                            k3 = rate(z + 0.5 * dt * k2), k4 = rate(z + dt * k3);
      z += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
      double slip;
      Eigen::Vector2d forces;
      rate(z, &slip, &forces);
      EXPECT_GT(forces(0), 0.0);  // it stays on the corner
      if (sliding == 0.0) {
        EXPECT_LE(std::abs(forces(1)), mu * forces(0));  // within the cone
      } else {
        EXPECT_GT(slip * sliding, 0.0);  // slipping one way throughout
      }
    }
    return z;
  }
};

// A block tilted by 0.1 rad and released from rest on its lower corner, on a rough floor: with
// mu = 1 the corner sticks and the block pivots about it; with mu = 0.1 the corner slides out
// from under it. Up to t = 0.05 s (before the other corner lands) the event-driven scheme, its
// held corner under Coulomb's law, meets the pivot's equations integrated on their own by
// Runge-Kutta to 1e-9 in x, y, theta and their rates; the pivot keeps the energy, the slide
// loses it to the slip.
TEST(RockingBlock, OnARoughFloorPivotsOrSlidesAsItsEquations) {
  const double end = 0.05;
  for (const double mu : {1.0, 0.1}) {
    RockingBlock block;
    block.drop_height = 0.0;
    block.friction = mu;
    auto system = block.build();
    const double start_energy = block.energy(*system);
    SimulationSetup setup;
    setup.integrator.ode.relative_tolerance = 1e-12;
    setup.integrator.ode.absolute_tolerance = 1e-15;
    kernel::Simulation simulation = make_simulation(system, setup);
    Rocking rocking;
    rocking.block = &block;
    simulation.add_observer(rocking);
    simulation.run(0.0, end);
    EXPECT_TRUE(rocking.impacts.empty());
    // the lower corner is -w/2; from rest it sticks if it can, else slips where the stick's
    // force would push it
    Pivot pivot{block, -1.0, mu};
    const Eigen::Vector4d start(0.0, block.tilt, 0.0, 0.0);
    Eigen::Vector2d forces;
    pivot.rate(start, nullptr, &forces);
    if (std::abs(forces(1)) > mu * forces(0)) pivot.sliding = forces(1) > 0.0 ? -1.0 : 1.0;
    EXPECT_EQ(pivot.sliding != 0.0, mu < 0.5);
    const Eigen::Vector4d z = pivot.run(start, end, 1e-6);
    const Eigen::VectorXd& q = system->system(0).position();
    const Eigen::VectorXd& v = system->system(0).velocity();
    const double error = std::max({std::abs(q(0) - z(0)), std::abs(q(2) - z(1)),
                                   std::abs(v(0) - z(2)), std::abs(v(2) - z(3))});
    const double lost = start_energy - block.energy(*system);
    std::printf(
        "mu %.1f: %s, theta %.4f -> %.6f rad, x %+.3e m; against its equations %.1e; "
        "energy lost %.3e of %.6f J\n",
        mu, pivot.sliding != 0.0 ? "slides" : "pivots", block.tilt, q(2), q(0), error, lost,
        start_energy);
    EXPECT_LT(error, 1e-9) << "mu " << mu;
    if (pivot.sliding == 0.0) {
      EXPECT_LT(std::abs(lost), 1e-9 * start_energy);
    } else {
      EXPECT_GT(lost, 1e-3 * start_energy);
    }
  }
}

}  // namespace
}  // namespace mimpact::models
