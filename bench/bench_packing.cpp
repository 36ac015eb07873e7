// The cost of a planar packing's impact (issue 12, item e): a hexagonal packing of side x side
// steel beads struck at the middle of its bottom edge at 1 m/s. The impulse steps run at the
// delta_p that puts their post-impact velocities within 1e-4 m/s of the extrapolated answer
// (scripts/packing_scale.py measures it: the error grows with the packing, whose impact lasts
// longer); the adaptive LZB at tolerance 1e-4, whose elastic switches stay within its steps
// (docs/design/adaptive_lzb.md), so that its work follows the contacts reached (located, they
// made it grow as their square: 13 s at 1 024 beads). The asynchronous steps
// (docs/model.md, section 14) kick each contact at its own pace, so that their work follows
// the contacts the wave reaches. Counters: the steps, the contacts
// integrated per step, the contacts the wave reached; time per impact in seconds.
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
         R"(], "radius": 0.005, "velocity": [0.0, 1.0]}], "impact": )" + impact +
         // the LZB impact alone: its check against the moving geometry is another method's run
         R"(, "configuration_check": {"enabled": false}})";
}

void run(benchmark::State& state, const std::string& impact) {
  const int side = int(state.range(0));
  const packings::PackingScene scene =
      packings::parse_packing_scene(hexagon(side, impact), "bench packing");
  const packings::PackingModel model = packings::build_packing_model(scene);
  granular::SceneRun run;
  for (auto _ : state) {
    run = packings::run_packing_scene(scene, model);
    benchmark::DoNotOptimize(run.impact.velocity_after.data());
  }
  const numerics::ImpactResult& lzb = run.impact.result;
  state.counters["beads"] = double(model.bead_count);
  state.counters["contacts"] = double(model.contact_count());
  state.counters["steps"] = double(lzb.steps);
  state.counters["contacts_per_step"] = double(lzb.contact_steps) / double(lzb.steps);
  state.counters["contacts_reached"] = double((lzb.max_force.array() > 0.0).count());
}

void BM_PackingAdaptive(benchmark::State& state) {
  run(state, R"({"integrator": "adaptive", "tolerance": 1e-4})");
}
// range(1): delta_p in 1e-9 N s
void BM_PackingImpulseSteps(benchmark::State& state) {
  run(state, R"({"delta_p": )" + std::to_string(state.range(1)) + "e-9}");
}

// range(1): delta_p in 1e-9 N s
void BM_PackingAsynchronous(benchmark::State& state) {
  run(state,
      R"({"integrator": "asynchronous", "delta_p": )" + std::to_string(state.range(1)) + "e-9}");
}

void one_impact(benchmark::internal::Benchmark* benchmark) {
  benchmark->Iterations(1)->Unit(benchmark::kSecond);
}
// 256 beads (16 x 16), 1 024 (32 x 32), 3 136 (56 x 56), 10 000 (100 x 100)
BENCHMARK(BM_PackingAdaptive)->Arg(16)->Arg(32)->Arg(56)->Arg(100)->Apply(one_impact);
// 256, 1 024, 3 136 (56 x 56) and 10 000 (100 x 100) beads, each at the delta_p within 1e-4
BENCHMARK(BM_PackingImpulseSteps)
    ->Args({16, 100})
    ->Args({32, 50})
    ->Args({56, 50})
    ->Args({100, 25})
    ->Apply(one_impact);
// the asynchronous steps (steps: kicks; contacts_per_step: 1), each size at the delta_p within
// 1e-4: their error at a given delta_p is 3 to 5 times smaller
BENCHMARK(BM_PackingAsynchronous)
    ->Args({16, 400})
    ->Args({32, 200})
    ->Args({56, 200})
    ->Args({100, 100})
    ->Apply(one_impact);

}  // namespace

BENCHMARK_MAIN();
