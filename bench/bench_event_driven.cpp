// Newton's cradle through the event-driven scheme (issue 10 e): one second of swinging, eleven
// impacts, with each LZB impact integrated by the impulse steps at relative delta_p 1e-4 or by
// the adaptive integrator. The counters give the energy error after the second and the time
// spent in the impacts alone.
#include <benchmark/benchmark.h>

#include <cmath>

#include "mimpact/models/newtons_cradle.hpp"
#include "mimpact/models/simulation_setup.hpp"

namespace {

using namespace mimpact;

struct ImpactTime : kernel::SimulationObserver {
  void on_impact(const kernel::Simulation&, const kernel::ImpactReport& report) override {
    seconds += report.wall_time;
  }
  double seconds = 0.0;
};

void swing_one_second(benchmark::State& state, const plugins::LzbImpactOptions& impacts) {
  const models::NewtonsCradle cradle;  // five pendulums, e = 1
  double energy_error = 0.0, impact_seconds = 0.0;
  for (auto _ : state) {
    state.PauseTiming();
    auto system = cradle.build();
    const double start = cradle.energy(*system);
    kernel::Simulation simulation = models::make_simulation(system, {.impacts = impacts});
    ImpactTime impact_time;
    simulation.add_observer(impact_time);
    state.ResumeTiming();
    simulation.run(0.0, 1.0);
    state.PauseTiming();
    energy_error = std::abs(cradle.energy(*system) / start - 1.0);
    impact_seconds = impact_time.seconds;
    state.ResumeTiming();
  }
  state.counters["energy_error"] = energy_error;
  state.counters["impact_ms"] = 1e3 * impact_seconds;
}

void BM_CradleImpulseSteps(benchmark::State& state) {
  plugins::LzbImpactOptions impacts;
  impacts.relative_delta_p = 1e-4;
  swing_one_second(state, impacts);
}
BENCHMARK(BM_CradleImpulseSteps)->Unit(benchmark::kMillisecond);

void BM_CradleAdaptive(benchmark::State& state) {
  plugins::LzbImpactOptions impacts;
  impacts.integrator = plugins::LzbIntegrator::adaptive;
  impacts.tolerance = double(state.range(0)) * 1e-12;
  swing_one_second(state, impacts);
}
BENCHMARK(BM_CradleAdaptive)->Arg(1000)->Arg(100)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
