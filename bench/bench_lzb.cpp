// Cost of the LZB impulse-step integrator: the whole impact of chain C1 at the paper's
// finest delta_p, and the cost of a step against the length of the chain.
#include <benchmark/benchmark.h>

#include <string>

#include "mimpact/chains/chain_impact.hpp"
#include "mimpact/chains/chain_model.hpp"
#include "mimpact/chains/chain_scene.hpp"
#include "mimpact/granular/impact_recorder.hpp"

namespace {

using namespace mimpact;

chains::ChainModel c1_like_chain(int beads) {
  const std::string text =
      R"({"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
          "chain": {"segments": [{"count": )" +
      std::to_string(beads) + R"(, "radius": 0.010}]},
          "strikers": [{"side": "left", "radius": 0.010, "velocity": 1.0}]})";
  return chains::build_chain_model(chains::parse_chain_scene(text, "bench chain"));
}

// The whole impact of C1 at delta_p = 1e-6 (458 933 steps in the paper; 7.23 s there,
// 1.23 s for Siconos 4.5 on this machine).
void BM_C1WholeImpact(benchmark::State& state) {
  const chains::ChainModel model = chains::build_chain_model(
      chains::load_chain_scene(MIMPACT_SOURCE_DIR "/examples/scenes/c1.json"));
  numerics::LzbImpulseIntegrator integrator({.delta_p = 1e-6});
  numerics::ImpactResult result;
  for (auto _ : state) {
    result = integrator.integrate(model.H, model.u_minus, model.laws);
    benchmark::DoNotOptimize(result.impulse.data());
  }
  state.counters["steps"] = double(result.steps);
  state.counters["contacts_per_step"] = double(result.contact_steps) / double(result.steps);
}
BENCHMARK(BM_C1WholeImpact)->Unit(benchmark::kMillisecond);

chains::ChainModel c1_model() {
  return chains::build_chain_model(
      chains::load_chain_scene(MIMPACT_SOURCE_DIR "/examples/scenes/c1.json"));
}

// ||v+ - v+_Hertz||_inf / ||v+_Hertz||_inf: for e = 1 both LZB integrators converge to the
// Hertz chain, here the compliant method at tolerance 1e-12 (an independent integration).
double c1_velocity_error(const Eigen::VectorXd& velocity) {
  static const Eigen::VectorXd exact = [] {
    const chains::ChainModel model = c1_model();
    granular::CompliantSpec spec;
    spec.tolerance = 1e-12;
    return chains::simulate_chain_compliant(model, spec, {}).impact.velocity_after;
  }();
  return (velocity - exact).cwiseAbs().maxCoeff() / exact.cwiseAbs().maxCoeff();
}

void c1_through_kernel(benchmark::State& state, const plugins::LzbImpactOptions& options) {
  const chains::ChainModel model = c1_model();
  granular::ImpactOutcome impact;
  for (auto _ : state) {
    impact = chains::simulate_chain_impact(model, options);
    benchmark::DoNotOptimize(impact.velocity_after.data());
  }
  state.counters["steps"] = double(impact.result.steps);
  state.counters["velocity_error"] = c1_velocity_error(impact.velocity_after);
}

// The same impact through the kernel, as `mimpact chain` runs it: the chain's system, the
// event-driven integrator, the LZB impact problem, Delassus assembly, the simulation loop.
void BM_C1ThroughKernel(benchmark::State& state) {
  plugins::LzbImpactOptions options;
  options.delta_p = 1e-6;
  c1_through_kernel(state, options);
}
BENCHMARK(BM_C1ThroughKernel)->Unit(benchmark::kMillisecond);

// C1 by the adaptive integrator of the continuous limit at tolerance 1e-6 (issue 10 c: an
// error of 1e-6 at least 30 times faster than the impulse steps at delta_p = 1e-6, whose
// error is 7.6e-5).
void BM_C1Adaptive(benchmark::State& state) {
  plugins::LzbImpactOptions options;
  options.integrator = plugins::LzbIntegrator::adaptive;
  options.tolerance = 1e-6;
  c1_through_kernel(state, options);
}
BENCHMARK(BM_C1Adaptive)->Unit(benchmark::kMillisecond);

// The whole impact of C1-like chains of 1 000, 10 000 and 100 000 beads at tolerance 1e-6, by
// the adaptive LZB integrator and by the compliant method (run until the wave has left: it
// forms within 2e-4 s and crosses a bead in 3.2e-5 s). Their work follows the wave, so the
// time grows as the length (issue 10 d: time(10 000) / time(1 000) <= 12).
void BM_ChainLengthAdaptive(benchmark::State& state) {
  const chains::ChainModel model = c1_like_chain(int(state.range(0)));
  plugins::LzbImpactOptions options;
  options.integrator = plugins::LzbIntegrator::adaptive;
  options.tolerance = 1e-6;
  granular::ImpactOutcome impact;
  for (auto _ : state) {
    impact = chains::simulate_chain_impact(model, options);
    benchmark::DoNotOptimize(impact.velocity_after.data());
  }
  state.counters["steps"] = double(impact.result.steps);
  state.counters["contacts_per_step"] =
      double(impact.result.contact_steps) / double(impact.result.steps);
  state.counters["last_velocity"] = impact.velocity_after(impact.velocity_after.size() - 1);
}
BENCHMARK(BM_ChainLengthAdaptive)
    ->Arg(1000)
    ->Arg(10000)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond);

void BM_ChainLengthCompliant(benchmark::State& state) {
  const chains::ChainModel model = c1_like_chain(int(state.range(0)));
  granular::CompliantSpec spec;
  spec.tolerance = 1e-6;
  spec.end_time = 2e-4 + 3.2e-5 * double(state.range(0));
  granular::CompliantRun run;
  for (auto _ : state) {
    run = chains::simulate_chain_compliant(model, spec, {});
    benchmark::DoNotOptimize(run.impact.velocity_after.data());
  }
  state.counters["steps"] = double(run.impact.result.steps);
  state.counters["most_bodies_in_motion"] = double(run.most_bodies_in_motion);
  state.counters["last_velocity"] = run.impact.velocity_after(run.impact.velocity_after.size() - 1);
}
BENCHMARK(BM_ChainLengthCompliant)
    ->Arg(1000)
    ->Arg(10000)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond);

// A fixed budget of impulse steps on chains of 20, 1 000 and 100 000 beads (the 20-bead
// impact ends before the budget). The work of a step follows the contacts in the wave, so
// the cost of a step must not grow with the chain.
void BM_ChainSteps(benchmark::State& state) {
  const chains::ChainModel model = c1_like_chain(int(state.range(0)));
  numerics::LzbImpulseIntegrator integrator({.delta_p = 1e-6, .max_steps = 400'000});
  numerics::ImpactResult result;
  for (auto _ : state) {
    result = integrator.integrate(model.H, model.u_minus, model.laws);
    benchmark::DoNotOptimize(result.impulse.data());
  }
  // per-iteration counts shown as a time per unit: seconds per step and per contact-step
  const auto per = benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert;
  state.counters["steps"] = double(result.steps);
  state.counters["contacts_per_step"] = double(result.contact_steps) / double(result.steps);
  state.counters["time_per_step"] = benchmark::Counter(double(result.steps), per);
  state.counters["time_per_contact_step"] = benchmark::Counter(double(result.contact_steps), per);
}
BENCHMARK(BM_ChainSteps)->Arg(20)->Arg(1000)->Arg(100000)->Unit(benchmark::kMillisecond);

// What a call costs before its first step: checking H and resetting the per-contact
// buffers, linear in the number of contacts.
void BM_ImpactSetup(benchmark::State& state) {
  const chains::ChainModel model = c1_like_chain(int(state.range(0)));
  numerics::LzbImpulseIntegrator integrator({.delta_p = 1e-6, .max_steps = 1});
  for (auto _ : state) {
    numerics::ImpactResult result = integrator.integrate(model.H, model.u_minus, model.laws);
    benchmark::DoNotOptimize(result.impulse.data());
  }
}
BENCHMARK(BM_ImpactSetup)->Arg(1000)->Arg(100000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
