// A block 0.1 m x 0.2 m dropped tilted by 0.1 rad on a frictionless floor, e = 0.5: it
// rocks from corner to corner with a contact Jacobian that turns with it, loses energy at
// every impact, and comes to rest on both corners, each carrying half its weight. Then the same
// block released from rest on its corner on a rough floor: at mu = 1 it pivots about the corner,
// at mu = 0.1 the corner slides out from under it (Coulomb's law on the held corner).
#include <cstdio>

#include "mimpact/models/rocking_block.hpp"
#include "mimpact/models/simulation_setup.hpp"

using namespace mimpact;

namespace {

class Rocking : public kernel::SimulationObserver {
 public:
  explicit Rocking(const models::RockingBlock& block) : block_(block) {}
  void on_impact(const kernel::Simulation& simulation,
                 const kernel::ImpactReport& report) override {
    if (impacts++ < 8) {
      const Eigen::VectorXd& q = simulation.system().system(0).position();
      std::printf("impact at t = %.6f s on %zu corner(s), theta = %+.2e rad, energy %.6f J\n",
                  report.time, report.interactions.size(), q(2),
                  block_.energy(simulation.system()));
    }
  }
  kernel::EventStatus on_step(const kernel::Simulation&, const kernel::StepReport& step) override {
    if (step.contact_forces) forces = *step.contact_forces;
    return kernel::EventStatus::proceed();
  }
  int impacts = 0;
  kernel::ContactForces forces;

 private:
  const models::RockingBlock& block_;
};

}  // namespace

int main(int argc, char* argv[]) try {
  const models::RockingBlock block;
  models::SimulationSetup setup;
  plugins::LzbImpactOptions defaults;
  defaults.relative_delta_p = 1e-3;
  setup.impacts = models::impact_options_from_command_line(argc, argv, defaults);
  kernel::Simulation simulation = models::make_simulation(block.build(), setup);
  Rocking rocking(block);
  simulation.add_observer(rocking);
  const kernel::RunSummary summary = simulation.run(0.0, 2.0);
  const Eigen::VectorXd& q = simulation.system().system(0).position();
  std::printf("%d impacts; at t = 2 s: theta = %.3e rad, persistent corners %zu, forces",
              rocking.impacts, q(2), simulation.system().index_sets().persistent.size());
  for (kernel::Index k = 0; k < rocking.forces.force.size(); ++k)
    std::printf(" %.6f", rocking.forces.force(k));
  std::printf(" N (m g / 2 = %.6f N)\n", block.mass * block.gravity / 2);
  std::printf("%lld events, %lld smooth steps, %.3f s of computation\n", (long long)summary.events,
              (long long)summary.smooth_steps, summary.wall_time);
  for (const double mu : {1.0, 0.1}) {
    models::RockingBlock rough = block;
    rough.drop_height = 0.0;
    rough.friction = mu;
    kernel::Simulation released = models::make_simulation(rough.build(), setup);
    Rocking rocking_on(rough);
    released.add_observer(rocking_on);
    const double start = rough.energy(released.system());
    std::printf("on a rough floor, mu = %.1f, released on its corner:\n", mu);
    released.run(0.0, 2.0);
    const Eigen::VectorXd& x = released.system().system(0).position();
    std::printf("at t = 2 s: x = %+.4f mm, theta = %.3e rad, energy lost %.4f of %.4f J\n",
                1e3 * x(0), x(2), start - rough.energy(released.system()), start);
  }
} catch (const std::exception& error) {
  std::fprintf(stderr, "%s\n", error.what());
  return 2;
}
