// An application on the installed package, public API only: a steel ball dropped on a steel
// floor (e = 0.8), simulated by the event-driven integrator and the LZB impact law chosen
// by name. Exits non-zero when the first bounce leaves at other than e times the impact speed.
#include <cmath>
#include <cstdio>
#include <mimpact/kernel/lagrangian_linear_tids.hpp>
#include <mimpact/kernel/linear_relation.hpp>
#include <mimpact/kernel/registry.hpp>
#include <mimpact/kernel/simulation.hpp>
#include <mimpact/plugins/lzb_law.hpp>
#include <mimpact/plugins/register_plugins.hpp>

using namespace mimpact;

class FirstBounce : public kernel::SimulationObserver {
 public:
  kernel::EventStatus on_step(const kernel::Simulation&, const kernel::StepReport& step) override {
    if (!step.impact) return kernel::EventStatus::proceed();
    before = step.impact->velocity_before(0);
    after = step.impact->result.velocity(0);
    return kernel::EventStatus::terminate("first bounce");
  }
  double before = 0.0, after = 0.0;
};

int main() {
  plugins::register_plugins();
  const double mass = 0.0327, radius = 0.01, gravity = 9.81, restitution = 0.8;
  kernel::LagrangianLinearTIDS::Matrices matrices;
  matrices.mass = Eigen::MatrixXd::Constant(1, 1, mass);
  matrices.external_force = Eigen::VectorXd::Constant(1, -mass * gravity);
  auto ball = std::make_shared<kernel::LagrangianLinearTIDS>(
      Eigen::VectorXd::Constant(1, 1.0), Eigen::VectorXd::Zero(1), matrices, "ball");
  auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  system->add(ball);
  system->add(std::make_shared<kernel::Interaction>(
      ball, std::make_shared<kernel::LinearRelation>(Eigen::RowVectorXd::Ones(1), -radius),
      std::make_shared<plugins::LzbLaw>(
          numerics::ContactLaw{.stiffness = 1.3e10, .restitution = restitution}),
      "floor"));
  kernel::Simulation simulation(
      system, kernel::integrators().create("event-driven"),
      {.impacts = kernel::impact_problems().create("lzb", {{"relative_delta_p", 1e-3}}),
       .contact_forces = kernel::contact_force_problems().create("acceleration-lcp")});
  FirstBounce bounce;
  simulation.add_observer(bounce);
  simulation.run(0.0, 1.0);
  const double expected_time = std::sqrt(2.0 * (1.0 - radius) / gravity);
  std::printf(
      "first bounce at t = %.9f s (free fall: %.9f s), %.6f m/s in, %.6f m/s out (e = %.2f)\n",
      simulation.time(), expected_time, -bounce.before, bounce.after, restitution);
  const bool right = std::abs(bounce.after + restitution * bounce.before) < 1e-9 &&
                     std::abs(simulation.time() - expected_time) < 1e-9;
  return right ? 0 : 1;
}
