// A column of ten steel beads resting on a steel floor, struck by an eleventh dropped from
// 5 cm: the floor and every contact carry the weight above before the strike, the wave
// goes down and back, and the column settles again.
#include <cstdio>

#include "mimpact/models/bead_column.hpp"
#include "mimpact/models/simulation_setup.hpp"

using namespace mimpact;

namespace {

class Column : public kernel::SimulationObserver {
 public:
  kernel::EventStatus on_step(const kernel::Simulation&, const kernel::StepReport& step) override {
    if (step.contact_forces) last_forces = *step.contact_forces;
    if (step.contact_forces && first_forces.interactions.empty())
      first_forces = *step.contact_forces;
    return kernel::EventStatus::proceed();
  }
  void on_impact(const kernel::Simulation&, const kernel::ImpactReport& report) override {
    if (impacts++ < 3)
      std::printf("impact at t = %.6f s among %zu contacts, %lld steps, lasting %.3g s\n",
                  report.time, report.interactions.size(), (long long)report.result.steps,
                  report.result.duration);
  }
  kernel::ContactForces first_forces, last_forces;
  int impacts = 0;
};

void print_forces(const char* when, const kernel::ContactForces& forces, double weight) {
  std::printf("%s (t = %.4f s), contact forces / bead weight:", when, forces.time);
  for (kernel::Index k = 0; k < forces.force.size(); ++k)
    std::printf(" %.6f", forces.force(k) / weight);
  std::printf("\n");
}

}  // namespace

int main(int argc, char* argv[]) try {
  const models::BeadColumn column;
  models::SimulationSetup setup;
  plugins::LzbImpactOptions defaults;
  defaults.relative_delta_p = 1e-3;
  setup.impacts = models::impact_options_from_command_line(argc, argv, defaults);
  kernel::Simulation simulation = models::make_simulation(column.build(), setup);
  Column observer;
  simulation.add_observer(observer);
  const kernel::RunSummary summary = simulation.run(0.0, 1.0);
  const double weight = column.mass() * column.gravity;
  print_forces("before the strike", observer.first_forces, weight);
  print_forces("settled", observer.last_forces, weight);
  std::printf("%d impacts, %lld events, %lld smooth steps, %.3f s of computation\n",
              observer.impacts, (long long)summary.events, (long long)summary.smooth_steps,
              summary.wall_time);
} catch (const std::exception& error) {
  std::fprintf(stderr, "%s\n", error.what());
  return 2;
}
