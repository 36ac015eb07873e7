// Where the event-driven integrator places events: a free fall with an analytic impact
// time, two contacts closing within one step, a grazing contact, and what a scene without
// forces does not build.
#include <gtest/gtest.h>

#include <cmath>

#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/linear_relation.hpp"
#include "mimpact/kernel/simulation.hpp"
#include "mimpact/plugins/acceleration_lcp_problem.hpp"
#include "mimpact/plugins/event_driven_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::plugins {
namespace {

using kernel::Index;
constexpr double kGravity = 9.81, kRadius = 0.01, kMass = 0.03;

std::shared_ptr<kernel::LagrangianLinearTIDS> falling_ball(double z, double v,
                                                           const std::string& name) {
  kernel::LagrangianLinearTIDS::Matrices matrices;
  matrices.mass = Eigen::MatrixXd::Constant(1, 1, kMass);
  matrices.external_force = Eigen::VectorXd::Constant(1, -kMass * kGravity);
  return std::make_shared<kernel::LagrangianLinearTIDS>(
      Eigen::VectorXd::Constant(1, z), Eigen::VectorXd::Constant(1, v), matrices, name);
}

std::shared_ptr<LzbLaw> steel_law(double restitution = 0.8) {
  numerics::ContactLaw law;
  law.stiffness = 1e10;
  law.restitution = restitution;
  return std::make_shared<LzbLaw>(law);
}

// g = sign * z + offset: the floor (sign +1, offset -R) or a ceiling (sign -1).
std::shared_ptr<kernel::Interaction> plane(std::shared_ptr<kernel::DynamicalSystem> ball,
                                           double sign, double offset, const std::string& name) {
  return std::make_shared<kernel::Interaction>(
      std::move(ball),
      std::make_shared<kernel::LinearRelation>(Eigen::RowVectorXd::Constant(1, sign), offset),
      steel_law(), name);
}

struct Outcome {
  std::vector<double> impact_times;
  std::vector<std::vector<Index>> impact_contacts;
  double lowest_gap = INFINITY;  // over the output samples
  kernel::RunSummary summary;
};

class Watch : public kernel::SimulationObserver {
 public:
  explicit Watch(Outcome& run) : run_(run) {}
  void on_impact(const kernel::Simulation&, const kernel::ImpactReport& report) override {
    run_.impact_times.push_back(report.time);
    run_.impact_contacts.push_back(report.interactions);
  }
  void on_output(const kernel::Simulation& simulation) override {
    for (Index j = 0; j < simulation.system().interaction_count(); ++j)
      run_.lowest_gap = std::min(run_.lowest_gap, simulation.system().interaction(j).gap());
  }

 private:
  Outcome& run_;
};

Outcome simulate(std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                 EventDrivenOptions options, double end, double output_interval = 0.0) {
  kernel::Simulation simulation(std::move(system), std::make_unique<EventDrivenIntegrator>(options),
                                {.impacts = std::make_unique<LzbImpactProblem>(),
                                 .contact_forces = std::make_unique<AccelerationLcpProblem>()});
  Outcome run;
  Watch watch(run);
  simulation.add_observer(watch);
  if (output_interval > 0.0) simulation.schedule_outputs(0.0, output_interval, end);
  run.summary = simulation.run(0.0, end);
  return run;
}

TEST(EventLocation, FreeFallImpactWithinTheRequestedTolerance) {
  const double height = 0.5;
  const double exact = std::sqrt(2.0 * (height - kRadius) / kGravity);
  for (double tolerance : {1e-6, 1e-8, 1e-10, 1e-12}) {
    auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
    auto ball = falling_ball(height, 0.0, "ball");
    system->add(ball);
    system->add(plane(ball, 1.0, -kRadius, "floor"));
    EventDrivenOptions options;
    options.ode.event_tolerance = tolerance;
    const Outcome run = simulate(system, options, exact * 1.01);
    ASSERT_EQ(run.impact_times.size(), 1u) << "tolerance " << tolerance;
    // placed after the crossing, by at most the tolerance
    EXPECT_GE(run.impact_times[0], exact - 1e-15) << "tolerance " << tolerance;
    EXPECT_LE(run.impact_times[0], exact + tolerance) << "tolerance " << tolerance;
  }
}

TEST(EventLocation, TwoContactsClosingInOneStepAreFoundInOrder) {
  // two balls 1 mm apart in height above one floor; one sample per step, so both
  // crossings fall between the same two samples
  const double low = 0.5, high = 0.501;
  auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  auto first = falling_ball(low, 0.0, "low"), second = falling_ball(high, 0.0, "high");
  system->add(first);
  system->add(second);
  system->add(plane(first, 1.0, -kRadius, "floor under low"));
  system->add(plane(second, 1.0, -kRadius, "floor under high"));
  EventDrivenOptions options;
  options.ode.samples_per_step = 1;
  options.ode.event_tolerance = 1e-12;
  const double t_low = std::sqrt(2.0 * (low - kRadius) / kGravity);
  const double t_high = std::sqrt(2.0 * (high - kRadius) / kGravity);
  const Outcome run = simulate(system, options, t_high * 1.001);
  ASSERT_EQ(run.impact_times.size(), 2u);
  EXPECT_NEAR(run.impact_times[0], t_low, 1e-12);
  EXPECT_NEAR(run.impact_times[1], t_high, 1e-12);
  EXPECT_EQ(run.impact_contacts[0], std::vector<Index>{0});
  EXPECT_EQ(run.impact_contacts[1], std::vector<Index>{1});
}

// A ball thrown up whose apex touches a ceiling (g = 0 with g' = 0 there) must neither
// bounce off it nor go through; one whose apex goes 0.1 um beyond must bounce, though both
// samples around the apex see an open gap.
TEST(EventLocation, GrazingContactNeitherImpactsNorPassesThrough) {
  const double z0 = 0.2, v0 = 1.0;
  const double apex = z0 + v0 * v0 / (2.0 * kGravity);
  for (double overshoot : {0.0, 1e-7}) {
    auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
    auto ball = falling_ball(z0, v0, "ball");
    system->add(ball);
    system->add(plane(ball, -1.0, apex + kRadius - overshoot - kRadius, "ceiling"));
    EventDrivenOptions options;
    options.ode.samples_per_step = 1;
    const double flight = 2.0 * v0 / kGravity;
    const Outcome run = simulate(system, options, 0.9 * flight, flight / 200);
    if (overshoot == 0.0) {
      EXPECT_EQ(run.summary.impacts, 0);
      EXPECT_GE(run.lowest_gap, -1e-12);
      EXPECT_NEAR(ball->velocity()(0), v0 - kGravity * 0.9 * flight, 1e-9);  // still free flight
    } else {
      EXPECT_EQ(run.summary.impacts, 1);
      EXPECT_GE(run.lowest_gap, -1e-12);
      EXPECT_LT(ball->velocity()(0), -0.5);  // sent down by the ceiling
    }
  }
}

}  // namespace
}  // namespace mimpact::plugins
