// The compliant integrator against closed forms: a two-body Hertz (and linear) collision's
// duration and peak force, u+ = -e u- of the hysteretic law, and an independent time-domain
// Hertz chain.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>

#include "../support/hertz_chain_reference.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/linear_relation.hpp"
#include "mimpact/kernel/simulation.hpp"
#include "mimpact/plugins/acceleration_lcp_problem.hpp"
#include "mimpact/plugins/compliant_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::plugins {
namespace {

using kernel::Index;

struct Collision {
  double duration = 0.0, peak = 0.0, separation_speed = 0.0;
};

// Two bodies on a line, the first at `speed` towards the second, touching at t = 0.
Collision collide(double m1, double m2, double speed, numerics::ContactLaw law,
                  const CompliantOptions& options = {}) {
  auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  kernel::LagrangianLinearTIDS::Matrices a, b;
  a.mass = Eigen::MatrixXd::Constant(1, 1, m1);
  b.mass = Eigen::MatrixXd::Constant(1, 1, m2);
  auto first = std::make_shared<kernel::LagrangianLinearTIDS>(
      Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, speed), a, "a");
  auto second = std::make_shared<kernel::LagrangianLinearTIDS>(Eigen::VectorXd::Constant(1, 0.02),
                                                               Eigen::VectorXd::Zero(1), b, "b");
  system->add(first);
  system->add(second);
  system->add(std::make_shared<kernel::Interaction>(
      first, second, std::make_shared<kernel::LinearRelation>(Eigen::RowVector2d(-1, 1), -0.02),
      std::make_shared<LzbLaw>(law), "c"));
  kernel::Simulation simulation(system, std::make_unique<CompliantIntegrator>(options));
  struct Opening : kernel::SimulationObserver {
    double time = -1.0;
    kernel::EventStatus on_step(const kernel::Simulation&,
                                const kernel::StepReport& step) override {
      if (!step.event || step.detaching.empty() || time >= 0.0)
        return kernel::EventStatus::proceed();
      time = step.time;
      return kernel::EventStatus::terminate("the contact has opened");
    }
  } opening;
  simulation.add_observer(opening);
  simulation.run(0.0, 1.0);
  Collision result;
  result.duration = opening.time;
  result.peak = simulation.integrator().contact_force_history()->max_force(0);
  result.separation_speed = second->velocity()(0) - first->velocity()(0);
  return result;
}

TEST(CompliantIntegrator, TwoBodyCollisionMatchesTheClosedForm) {
  const double m1 = 0.02, m2 = 0.05, speed = 0.7, reduced = m1 * m2 / (m1 + m2);
  for (double eta : {1.0, 1.5}) {
    numerics::ContactLaw law;
    law.stiffness = eta == 1.0 ? 2e6 : 5e9;
    law.exponent = eta;
    const Collision collision = collide(m1, m2, speed, law);
    const double a = 1.0 + eta;
    const double compression =
        std::pow(a * reduced * speed * speed / (2.0 * law.stiffness), 1.0 / a);
    // T = (2 delta_m / V) B(1/a, 1/2) / a; F_max = K delta_m^eta
    const double duration = 2.0 * compression / speed * std::tgamma(1.0 / a) *
                            std::sqrt(std::numbers::pi) / (a * std::tgamma(1.0 / a + 0.5));
    const double peak = law.stiffness * std::pow(compression, eta);
    EXPECT_NEAR(collision.duration, duration, 1e-8 * duration) << "eta " << eta;
    EXPECT_NEAR(collision.peak, peak, 1e-8 * peak) << "eta " << eta;
    EXPECT_NEAR(collision.separation_speed, speed, 1e-9 * speed) << "eta " << eta;
  }
}

// Two bodies of 0.03 kg touching, approaching at u (m/s), beside a third flying away at 1 m/s
// (the speed scale: relative_tolerance x 1 m/s is the resolved speed); the Hertz law of stiffness
// kSlowStiffness and restitution e. The run's steps, the pair's velocities after, and the work
// the ledger booked.
constexpr double kSlowMass = 0.03, kSlowStiffness = 5e9;
struct SlowCollision {
  std::int64_t smooth_steps = 0;
  double va = 0.0, vb = 0.0, work = 0.0;
};
SlowCollision slow_collision(double u, double e) {
  auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  kernel::LagrangianLinearTIDS::Matrices unit;
  unit.mass = Eigen::MatrixXd::Constant(1, 1, kSlowMass);
  auto body = [&](double q, double v, const char* name) {
    auto made = std::make_shared<kernel::LagrangianLinearTIDS>(
        Eigen::VectorXd::Constant(1, q), Eigen::VectorXd::Constant(1, v), unit, name);
    system->add(made);
    return made;
  };
  body(-1.0, -1.0, "far, flying away");
  auto a = body(0.0, u, "a");
  auto b = body(0.02, 0.0, "b");  // touching: the join comes after the resolution's overlap
  numerics::ContactLaw law;
  law.stiffness = kSlowStiffness;
  law.restitution = e;
  system->add(std::make_shared<kernel::Interaction>(
      a, b, std::make_shared<kernel::LinearRelation>(Eigen::RowVector2d(-1, 1), -0.02),
      std::make_shared<LzbLaw>(law), "slow"));
  kernel::Simulation simulation(system, std::make_unique<CompliantIntegrator>());
  const kernel::RunSummary summary = simulation.run(0.0, 1.0);
  return {summary.smooth_steps, a->velocity()(0), b->velocity()(0),
          simulation.integrator().contact_force_history()->work(0)};
}

// An instantaneous collision: u+ = -e u- at once, with no integration step, momentum kept, and
// its work booked in the ledger exactly as the kinetic energy changes.
void expect_instantaneous(double u, double e) {
  const SlowCollision after = slow_collision(u, e);
  EXPECT_EQ(after.smooth_steps, 0) << "u " << u << ", e " << e;
  EXPECT_NEAR(after.vb - after.va, e * u, 1e-15 * u) << "u " << u << ", e " << e;
  EXPECT_NEAR(after.va + after.vb, u, 1e-15 * u) << "momentum, u " << u << ", e " << e;
  const double lost = 0.5 * kSlowMass * (u * u - after.va * after.va - after.vb * after.vb);
  EXPECT_NEAR(after.work, lost, 1e-12 * 0.5 * kSlowMass * u * u) << "u " << u << ", e " << e;
  EXPECT_NEAR(lost, (1 - e * e) * 0.25 * kSlowMass * u * u, 1e-12 * kSlowMass * u * u)
      << "u " << u << ", e " << e;
}

// A collision slower than relative_tolerance x the fastest initial speed (here 5e-11 m/s
// against 1e-10 x 1 m/s) is taken as instantaneous.
TEST(CompliantIntegrator, CollisionsBelowTheResolvedSpeedAreInstantaneous) {
  for (double e : {1.0, 0.5}) expect_instantaneous(5e-11, e);
}

// So is one faster than that whose isolated collision would turn before its overlap reaches the
// joining overlap delta_res (1e-12 m by default): K delta_res^2.5 / 2.5 > u^2 / (2 H), H = 2 / m.
// Integrated, it joined at delta_res under the force K delta_res^1.5 its approach never paid for,
// and the pair left faster than it came (at 0.6 of that speed: 1.8 times u for e = 1, 1.9
// times e u for e = 0.5).
TEST(CompliantIntegrator, CollisionsThatTurnBelowTheJoiningOverlapAreInstantaneous) {
  const double resolution = CompliantOptions{}.overlap_resolution;
  const double turning =
      std::sqrt(2.0 * (2.0 / kSlowMass) * kSlowStiffness * std::pow(resolution, 2.5) / 2.5);
  const double u = 0.6 * turning;
  ASSERT_GT(u, CompliantOptions{}.ode.relative_tolerance * 1.0);  // above the resolved speed
  for (double e : {1.0, 0.5}) expect_instantaneous(u, e);
}

// The unloading curve F_M ((delta - delta_r) / (delta_M - delta_r))^eta gives back e^2 of the
// compression work: two bodies leave at e times their approach speed.
TEST(CompliantIntegrator, HystereticContactRestoresEnergeticRestitution) {
  for (double e : {0.3, 0.8}) {
    numerics::ContactLaw law;
    law.stiffness = 5e9;
    law.restitution = e;
    const Collision collision = collide(0.02, 0.05, 0.7, law);
    EXPECT_NEAR(collision.separation_speed, e * 0.7, 1e-8) << "e " << e;
  }
}

// A run that needs more time steps than max_steps is stopped with an error naming the limit,
// not left to run (a striker at 1e300 m/s needs steps of 1e-103 s).
TEST(CompliantIntegrator, StepLimitEndsTheRunWithAnError) {
  numerics::ContactLaw law;
  law.stiffness = 1e10;
  CompliantOptions options;
  options.max_steps = 20;
  try {
    collide(0.03, 0.03, 1.0, law, options);
    ADD_FAILURE() << "a Hertz collision in 20 steps at tolerance 1e-10";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("max_steps = 20 time steps taken"), std::string::npos)
        << error.what();
  }
  options.max_steps = 0;
  EXPECT_THROW(CompliantIntegrator{options}, InvalidInput);
}

TEST(CompliantIntegrator, MonoStiffnessWithDissipationIsRefused) {
  numerics::ContactLaw law;
  law.stiffness = 5e9;
  law.restitution = 0.5;
  law.model = numerics::ComplianceModel::mono_stiffness;
  EXPECT_THROW(collide(0.02, 0.05, 0.7, law), InvalidInput);
}

}  // namespace
}  // namespace mimpact::plugins
