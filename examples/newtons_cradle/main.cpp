// Newton's cradle of five steel pendulums, e = 1: the first is released from 0.3 rad. The
// first impact is compared with the LZB outcome of the equivalent chain of balls, and the
// energy is followed through the impacts.
#include <cmath>
#include <cstdio>

#include "mimpact/models/newtons_cradle.hpp"
#include "mimpact/models/simulation_setup.hpp"

using namespace mimpact;

namespace {

class Impacts : public kernel::SimulationObserver {
 public:
  explicit Impacts(const models::NewtonsCradle& cradle) : cradle_(cradle) {}
  void on_start(const kernel::Simulation& simulation) override {
    start_energy = cradle_.energy(simulation.system());
  }
  void on_impact(const kernel::Simulation& simulation,
                 const kernel::ImpactReport& report) override {
    const kernel::NonSmoothDynamicalSystem& system = simulation.system();
    std::printf("impact at t = %.6f s, %zu contacts, %lld steps; ball speeds (m/s):", report.time,
                report.interactions.size(), (long long)report.result.steps);
    for (kernel::Index k = 0; k < system.system_count(); ++k)
      std::printf(" %.5f", cradle_.length * system.system(k).velocity()(0));
    std::printf("; energy %+.2e relative\n", cradle_.energy(system) / start_energy - 1.0);
  }
  double start_energy = 0.0;

 private:
  const models::NewtonsCradle& cradle_;
};

}  // namespace

int main(int argc, char* argv[]) try {
  const models::NewtonsCradle cradle;
  models::SimulationSetup setup;
  plugins::LzbImpactOptions defaults;
  defaults.relative_delta_p = 1e-4;
  setup.impacts = models::impact_options_from_command_line(argc, argv, defaults);
  kernel::Simulation simulation = models::make_simulation(cradle.build(), setup);
  Impacts impacts(cradle);
  simulation.add_observer(impacts);
  const kernel::RunSummary summary = simulation.run(0.0, 1.0);
  std::printf("%lld impacts, %lld events, %lld smooth steps, %.3f s; energy at t = 1 s: %+.2e\n",
              (long long)summary.impacts, (long long)summary.events,
              (long long)summary.smooth_steps, summary.wall_time,
              cradle.energy(simulation.system()) / impacts.start_energy - 1.0);
} catch (const std::exception& error) {
  std::fprintf(stderr, "%s\n", error.what());
  return 2;
}
