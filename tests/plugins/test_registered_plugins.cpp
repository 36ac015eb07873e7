// The plugins are chosen by name through the kernel's registries.
#include <gtest/gtest.h>

#include <string>

#include "mimpact/common/error.hpp"
#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/linear_relation.hpp"
#include "mimpact/kernel/registry.hpp"
#include "mimpact/kernel/simulation.hpp"
#include "mimpact/plugins/event_driven_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"
#include "mimpact/plugins/lzb_law.hpp"
#include "mimpact/plugins/register_plugins.hpp"

namespace mimpact::plugins {
namespace {

TEST(RegisteredPlugins, CreatedByNameWithTheirParameters) {
  register_plugins();
  auto integrator = kernel::integrators().create("event-driven", {{"event_tolerance", 1e-12}});
  EXPECT_EQ(integrator->name(), "event-driven");
  EXPECT_EQ(dynamic_cast<EventDrivenIntegrator&>(*integrator).options().ode.event_tolerance, 1e-12);

  auto impacts = kernel::impact_problems().create("lzb", {{"delta_p", 1e-7}, {"dense_up_to", 4}});
  const auto& lzb = dynamic_cast<LzbImpactProblem&>(*impacts);
  EXPECT_EQ(lzb.options().delta_p, 1e-7);
  EXPECT_EQ(lzb.options().impulse_steps.dense_up_to, 4);

  EXPECT_EQ(kernel::contact_force_problems().create("acceleration-lcp")->name(),
            "acceleration-lcp");
  EXPECT_THROW(kernel::impact_problems().create("lzb", {{"deltap", 1e-7}}), InvalidInput);
  EXPECT_THROW(kernel::impact_problems().create("lzb", {{"delta_p", -1.0}}), InvalidInput);
  EXPECT_THROW(kernel::integrators().create("time-stepping"), InvalidInput);
}

// Integer parameters travel as doubles: a fraction or a value past the type is named, not
// truncated or wrapped.
TEST(RegisteredPlugins, IntegerParametersMustBeWholeAndInRange) {
  register_plugins();
  auto expect_named = [](auto create, const std::string& message) {
    try {
      create();
      ADD_FAILURE() << "no error for " << message;
    } catch (const InvalidInput& error) {
      EXPECT_NE(std::string(error.what()).find(message), std::string::npos) << error.what();
    }
  };
  expect_named(
      [] {
        kernel::impact_problems().create("lzb", {{"dense_up_to", 2.7}});
      },
      "dense_up_to = 2.7 is invalid; allowed: an integer in [0, ");
  expect_named(
      [] {
        kernel::impact_problems().create("lzb", {{"max_steps", 1e300}});
      },
      "max_steps = 1e+300 is invalid");
  expect_named(
      [] {
        kernel::integrators().create("event-driven", {{"samples_per_step", 0.5}});
      },
      "samples_per_step = 0.5 is invalid");
  expect_named(
      [] {
        kernel::contact_force_problems().create("acceleration-lcp", {{"max_pivots", -1}});
      },
      "max_pivots = -1 is invalid");
  auto impacts = kernel::impact_problems().create("lzb", {{"max_steps", 1e6}});
  EXPECT_EQ(dynamic_cast<LzbImpactProblem&>(*impacts).options().impulse_steps.max_steps, 1'000'000);
}

// A ball of 1 kg on a vertical line, a floor at z = 0 with a linear spring law (K = 1e6
// N/m, e = 0.8); it starts at `height` (m) moving at `speed` (m/s), under `gravity` (m/s^2).
std::shared_ptr<kernel::NonSmoothDynamicalSystem> ball(double height, double speed,
                                                       double gravity) {
  kernel::LagrangianLinearTIDS::Matrices matrices;
  matrices.mass = Eigen::MatrixXd::Identity(1, 1);
  if (gravity != 0.0) matrices.external_force = Eigen::VectorXd::Constant(1, -gravity);
  auto body = std::make_shared<kernel::LagrangianLinearTIDS>(
      Eigen::VectorXd::Constant(1, height), Eigen::VectorXd::Constant(1, speed), matrices, "ball");
  auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  system->add(body);
  system->add(std::make_shared<kernel::Interaction>(
      body, std::make_shared<kernel::LinearRelation>(Eigen::RowVectorXd::Ones(1), 0.0),
      std::make_shared<LzbLaw>(
          numerics::ContactLaw{.stiffness = 1e6, .exponent = 1.0, .restitution = 0.8}),
      "floor"));
  return system;
}

// Every name of every registry is created with every parameter it takes (at its default,
// through the reader of parameters) and runs a ball bouncing off a floor without gravity:
// it leaves at e times its approach speed. Every contact force problem then holds a ball at
// rest on the floor with the force m g. A plugin registered later is run here as well.
TEST(RegisteredPlugins, EveryNameIsCreatedWithAllItsParametersAndRuns) {
  register_plugins();
  const auto& integrators = kernel::integrators();
  const auto& impacts = kernel::impact_problems();
  const auto& forces = kernel::contact_force_problems();
  int runs = 0;
  for (const std::string& integrator : integrators.names()) {
    const auto needs = integrators.create(integrator)->needs();
    const std::vector<std::string> impact_names =
        needs.impacts ? impacts.names() : std::vector<std::string>{""};
    const std::vector<std::string> force_names =
        needs.contact_forces ? forces.names() : std::vector<std::string>{""};
    for (const std::string& impact : impact_names) {
      for (const std::string& force : force_names) {
        kernel::SimulationProblems problems;
        if (!impact.empty()) problems.impacts = impacts.create(impact, impacts.defaults(impact));
        if (!force.empty()) problems.contact_forces = forces.create(force, forces.defaults(force));
        auto system = ball(1e-3, -1.0, 0.0);
        kernel::Simulation simulation(
            system, integrators.create(integrator, integrators.defaults(integrator)),
            std::move(problems));
        simulation.run(0.0, 6e-3);  // it arrives at 1 ms; the contact lasts at most 3.1 ms
        EXPECT_NEAR(system->system(0).velocity()(0), 0.8, 1e-8)
            << integrator << " with " << impact << " and " << force;
        ++runs;
      }
    }
  }
  EXPECT_GE(runs, 2);
  for (const std::string& force : forces.names()) {
    auto system = ball(0.0, 0.0, 9.81);
    kernel::Simulation simulation(
        system, integrators.create("event-driven"),
        {.impacts = impacts.create("lzb"), .contact_forces = forces.create(force)});
    struct Resting : kernel::SimulationObserver {
      kernel::EventStatus on_step(const kernel::Simulation&,
                                  const kernel::StepReport& step) override {
        if (step.contact_forces) lambda = step.contact_forces->force(0);
        return kernel::EventStatus::proceed();
      }
      double lambda = 0.0;
    } resting;
    simulation.add_observer(resting);
    simulation.run(0.0, 0.1);
    EXPECT_NEAR(resting.lambda, 9.81, 1e-12) << force;
    EXPECT_NEAR(system->system(0).position()(0), 0.0, 1e-12) << force;
  }
}

// The defaults a registry lists read back as the options' defaults.
TEST(RegisteredPlugins, DefaultsAreTheOptionsDefaults) {
  register_plugins();
  EXPECT_EQ(kernel::integrators().defaults("event-driven"),
            kernel::to_parameters(EventDrivenOptions{}));
  EXPECT_EQ(kernel::impact_problems().defaults("lzb"), kernel::to_parameters(LzbImpactOptions{}));
  // the step is a choice (delta_p or relative_delta_p), listed only when made
  EXPECT_FALSE(kernel::impact_problems().defaults("lzb").contains("delta_p"));
  EXPECT_FALSE(kernel::impact_problems().defaults("lzb").contains("fixed_thresholds"));
}

}  // namespace
}  // namespace mimpact::plugins
