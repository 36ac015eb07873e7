// Example c: Newton's cradle of 3 to 5 pendulums in angles, nonlinear contact relations.
// Its first impact is the LZB impact of the equivalent chain of balls, and for e = 1 it
// keeps its energy.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "mimpact/granular/hertz.hpp"
#include "mimpact/models/newtons_cradle.hpp"
#include "mimpact/models/simulation_setup.hpp"
#include "mimpact/numerics/delassus.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace mimpact::models {
namespace {

struct FirstImpact : kernel::SimulationObserver {
  void on_impact(const kernel::Simulation& simulation, const kernel::ImpactReport& r) override {
    if (report) return;
    report = r;
    for (kernel::Index k = 0; k < simulation.system().system_count(); ++k)
      angular_velocities.push_back(simulation.system().system(k).velocity()(0));
  }
  std::optional<kernel::ImpactReport> report;
  std::vector<double> angular_velocities;
};

// The balls at the bottom of their swings: a chain of equal masses whose first ball comes
// at `speed`; its LZB outcome with the same laws and the same delta_p.
Eigen::VectorXd chain_outcome(const NewtonsCradle& cradle, double speed, double delta_p) {
  const int n = cradle.pendulums;
  Eigen::SparseMatrix<double> W(n, n - 1);
  for (int i = 0; i + 1 < n; ++i) {
    W.insert(i, i) = -1.0;
    W.insert(i + 1, i) = 1.0;
  }
  const Eigen::VectorXd inverse_mass = Eigen::VectorXd::Constant(n, 1.0 / cradle.mass());
  const numerics::Delassus delassus(W, inverse_mass);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
  v(0) = speed;
  numerics::ContactLaw law;
  law.stiffness = cradle.hertz_stiffness();
  law.restitution = cradle.restitution;
  const std::vector<numerics::ContactLaw> laws(std::size_t(n - 1), law);
  numerics::LzbImpulseIntegrator integrator({.delta_p = delta_p});
  const numerics::ImpactResult result =
      integrator.integrate(Eigen::MatrixXd(delassus.H()), W.transpose() * v, laws);
  return v + delassus.mobility() * result.impulse;
}

TEST(NewtonsCradle, FirstImpactIsTheLzbImpactOfTheBallChain) {
  for (int pendulums : {3, 4, 5}) {
    NewtonsCradle cradle;
    cradle.pendulums = pendulums;
    SimulationSetup setup;
    setup.impacts.relative_delta_p = 1e-4;
    kernel::Simulation simulation = make_simulation(cradle.build(), setup);
    FirstImpact first;
    simulation.add_observer(first);
    // the first pendulum reaches the bottom after a quarter period, ~0.225 s
    simulation.run(0.0, 0.3);
    ASSERT_TRUE(first.report) << pendulums;
    EXPECT_EQ(first.report->interactions.size(), std::size_t(pendulums - 1));

    // its speed at the bottom: energy m g L (1 - cos theta_0), up to the located angle
    const double speed = -cradle.length * first.report->velocity_before(0) / cradle.length;
    const double expected_speed =
        std::sqrt(2.0 * cradle.gravity * cradle.length * (1.0 - std::cos(cradle.release_angle)));
    EXPECT_NEAR(speed, expected_speed, 1e-8 * expected_speed);
    const double delta_p = 1e-4 * speed / (2.0 / cradle.mass());
    const Eigen::VectorXd chain = chain_outcome(cradle, speed, delta_p);
    for (int i = 0; i < pendulums; ++i)
      EXPECT_NEAR(cradle.length * first.angular_velocities[i], chain(i), 1e-8 * speed)
          << pendulums << " pendulums, ball " << i;
  }
}

// With e = 1 the only energy errors are the ODE's and the impacts': over a second of
// swinging (eleven impacts, one multiple) they fall at second order in delta_p.
TEST(NewtonsCradle, ElasticCradleKeepsItsEnergy) {
  const NewtonsCradle cradle;  // five pendulums, e = 1
  std::vector<double> errors;
  for (double relative_delta_p : {1e-1, 1e-2, 1e-3}) {
    SimulationSetup setup;
    setup.impacts.relative_delta_p = relative_delta_p;
    auto system = cradle.build();
    const double start = cradle.energy(*system);
    kernel::Simulation simulation = make_simulation(system, setup);
    const kernel::RunSummary summary = simulation.run(0.0, 1.0);
    EXPECT_GE(summary.impacts, 2);  // out and back
    errors.push_back(std::abs(cradle.energy(*system) / start - 1.0));
    std::printf("relative delta_p %g: energy error after 1 s %.3g\n", relative_delta_p,
                errors.back());
  }
  EXPECT_LE(errors[2], 1e-7);
  EXPECT_GT(errors[0] / errors[1], 30.0);
  EXPECT_GT(errors[1] / errors[2], 30.0);
}

// Sums the LZB steps of every impact of a run.
struct ImpactSteps : kernel::SimulationObserver {
  void on_impact(const kernel::Simulation&, const kernel::ImpactReport& report) override {
    steps += report.result.steps;
    ++impacts;
  }
  std::int64_t steps = 0, impacts = 0;
};

// Issue 10 e: each impact integrated by the adaptive LZB at tolerance 1e-9 instead of the
// impulse steps. The energy after a second of swinging is kept to 1e-9 (the smooth motion's
// own error is 5e-10), with over ten times fewer LZB steps than the impulse steps at relative
// delta_p 1e-4, and both give the same swing: the balls' speeds after the second agree to the
// impulse steps' first-order error.
TEST(NewtonsCradle, AdaptiveImpactsKeepTheEnergyTo1e9) {
  const NewtonsCradle cradle;
  auto swing = [&](const plugins::LzbImpactOptions& impacts, ImpactSteps& counted) {
    auto system = cradle.build();
    const double start = cradle.energy(*system);
    kernel::Simulation simulation = make_simulation(system, {.impacts = impacts});
    simulation.add_observer(counted);
    simulation.run(0.0, 1.0);
    Eigen::VectorXd speeds(cradle.pendulums);
    for (int k = 0; k < cradle.pendulums; ++k)
      speeds(k) = cradle.length * system->system(k).velocity()(0);
    return std::pair{std::abs(cradle.energy(*system) / start - 1.0), speeds};
  };
  plugins::LzbImpactOptions adaptive, impulse_steps;
  adaptive.integrator = plugins::LzbIntegrator::adaptive;
  adaptive.tolerance = 1e-9;
  impulse_steps.relative_delta_p = 1e-4;
  ImpactSteps adaptive_steps, impulse_step_steps;
  const auto [adaptive_error, adaptive_speeds] = swing(adaptive, adaptive_steps);
  const auto [impulse_error, impulse_speeds] = swing(impulse_steps, impulse_step_steps);
  std::printf("energy error after 1 s: adaptive %.3g (%lld LZB steps), impulse steps %.3g (%lld)\n",
              adaptive_error, (long long)adaptive_steps.steps, impulse_error,
              (long long)impulse_step_steps.steps);
  EXPECT_LE(adaptive_error, 1e-9);
  EXPECT_EQ(adaptive_steps.impacts, impulse_step_steps.impacts);
  EXPECT_LE(10 * adaptive_steps.steps, impulse_step_steps.steps);
  const double scale = adaptive_speeds.cwiseAbs().maxCoeff();
  std::printf("largest speed difference %.3g of %.3g m/s\n",
              (adaptive_speeds - impulse_speeds).cwiseAbs().maxCoeff(), scale);
  EXPECT_LE((adaptive_speeds - impulse_speeds).cwiseAbs().maxCoeff(), 3e-4 * scale);
}

}  // namespace
}  // namespace mimpact::models
