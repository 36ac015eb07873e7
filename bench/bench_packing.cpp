// The cost of a planar packing's impact (issue 12, item e): a hexagonal packing of side x side
// steel beads struck at the middle of its bottom edge at 1 m/s, to a relative accuracy of about
// 1e-4, by the adaptive LZB (tolerance 1e-4) and by the impulse steps (delta_p = 2e-7 N s, 5e-5
// of the striker's momentum: their error on the 10 x 10 packing is 2.3e-4 m/s at 5e-7 and
// falls in proportion). Counters: the steps, the contacts integrated per step, the contacts
// the wave reached; time per impact in seconds.
#include <benchmark/benchmark.h>

#include <string>

#include "mimpact/packings/packing_run.hpp"

namespace {

using namespace mimpact;

std::string hexagon(int side, const std::string& impact) {
  return R"({"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
             "lattice": {"type": "hexagonal", "rows": )" +
         std::to_string(side) + R"(, "columns": )" + std::to_string(side) +
         R"(, "radius": 0.005}, "strikers": [{"target": [0, )" + std::to_string(side / 2) +
         R"(], "radius": 0.005, "velocity": [0.0, 1.0]}], "impact": )" + impact + "}";
}

void run(benchmark::State& state, const std::string& impact) {
  const int side = int(state.range(0));
  const packings::PackingScene scene =
      packings::parse_packing_scene(hexagon(side, impact), "bench packing");
  const packings::PackingModel model = packings::build_packing_model(scene);
  packings::PackingRun run;
  for (auto _ : state) {
    run = packings::run_packing_scene(scene, model);
    benchmark::DoNotOptimize(run.impact.velocity_after.data());
  }
  const numerics::LzbResult& lzb = run.impact.lzb;
  state.counters["beads"] = double(model.bead_count);
  state.counters["contacts"] = double(model.contact_count());
  state.counters["steps"] = double(lzb.steps);
  state.counters["contacts_per_step"] = double(lzb.contact_steps) / double(lzb.steps);
  state.counters["contacts_reached"] = double((lzb.max_force.array() > 0.0).count());
}

void BM_PackingAdaptive(benchmark::State& state) {
  run(state, R"({"integrator": "adaptive", "tolerance": 1e-4})");
}
void BM_PackingImpulseSteps(benchmark::State& state) { run(state, R"({"delta_p": 2e-7})"); }

// 256 beads (16 x 16), 1 024 (32 x 32), 3 136 (56 x 56) and 10 000 (100 x 100), one impact each
void packing_sides(benchmark::internal::Benchmark* benchmark) {
  for (int side : {16, 32, 56, 100}) benchmark->Arg(side);
  benchmark->Iterations(1)->Unit(benchmark::kSecond);
}
BENCHMARK(BM_PackingAdaptive)->Apply(packing_sides);
BENCHMARK(BM_PackingImpulseSteps)->Apply(packing_sides);

}  // namespace

BENCHMARK_MAIN();
