// The work-precision study: what accuracy each method buys with how much time. For chains
// C1, C2 (docs/experiments.md, e = 1), N (Nakagawa, e = 0.955), M type 2 (Melo, e = 0.965) and a
// 1 000-bead C1, the error of the post-impact velocities and of the peak forces against a
// reference, against the wall time of a run through the kernel (what `mimpact chain` pays),
// for the LZB impulse steps over delta_p, the adaptive LZB integrator over its tolerance and the
// compliant contacts integrated in time over theirs. A second family times the three against
// the length of the chain, up to 100 000 beads.
// bench/work_precision.py runs this program and writes docs/performance.md and its figures.
//
// References: for e = 1, the compliant method at a tight tolerance (the Hertz chain, which LZB
// converges to); for e < 1, where the two laws differ on re-loading, LZB itself, Richardson-
// extrapolated from delta_p = 1e-6 and 5e-7 of the striker's momentum.
#include <benchmark/benchmark.h>

#include <Eigen/Dense>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "mimpact/chains/chain_impact.hpp"
#include "mimpact/chains/chain_model.hpp"
#include "mimpact/chains/chain_scene.hpp"
#include "mimpact/granular/impact_recorder.hpp"

namespace {

using namespace mimpact;
using Eigen::VectorXd;

// What a run gives: post-impact velocities (m/s) and each contact's largest force (N).
struct Outcome {
  VectorXd velocity;
  VectorXd peak_force;
  std::int64_t steps = 0;
};

struct Case {
  std::string name;
  chains::ChainScene scene;
  double reference_tolerance;  // of the compliant reference, for e = 1
  std::vector<double> shares;  // delta_p / (m V) of the LZB runs
};

Outcome outcome_of(const granular::ImpactOutcome& impact) {
  return {impact.velocity_after, impact.result.max_force, impact.result.steps};
}

Outcome run_lzb(const Case& c, const chains::ChainModel& model, double share) {
  const double delta_p = share * granular::smallest_momentum(model);
  numerics::LzbOptions options = c.scene.impact.impulse_step_options();
  options.delta_p = delta_p;
  options.relative_delta_p.reset();
  return outcome_of(chains::simulate_chain_impact(model, options));
}

Outcome run_adaptive(const chains::ChainModel& model, double tolerance) {
  plugins::LzbImpactOptions options;
  options.integrator = plugins::LzbIntegrator::adaptive;
  options.tolerance = tolerance;
  return outcome_of(chains::simulate_chain_impact(model, options));
}

Outcome run_compliant(const Case& c, const chains::ChainModel& model, double tolerance) {
  granular::CompliantSpec spec = c.scene.compliant;
  spec.tolerance = tolerance;
  return outcome_of(chains::simulate_chain_compliant(model, spec, {}).impact);
}

bool elastic(const Case& c) { return c.scene.contact.restitution == 1.0; }

const Outcome& reference(const Case& c, const chains::ChainModel& model) {
  static std::map<std::string, Outcome> cache;
  auto found = cache.find(c.name);
  if (found != cache.end()) return found->second;
  Outcome outcome;
  if (elastic(c)) {
    outcome = run_compliant(c, model, c.reference_tolerance);
  } else {
    const Outcome coarse = run_lzb(c, model, 1e-6), fine = run_lzb(c, model, 5e-7);
    outcome.velocity = 2.0 * fine.velocity - coarse.velocity;
    outcome.peak_force = 2.0 * fine.peak_force - coarse.peak_force;
  }
  return cache.emplace(c.name, std::move(outcome)).first->second;
}

// ||x - reference||_inf / ||reference||_inf
double relative_error(const VectorXd& x, const VectorXd& reference) {
  return (x - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff();
}

enum class Method { impulse, adaptive, compliant };

const char* method_name(Method method) {
  switch (method) {
    case Method::impulse:
      return "impulse";
    case Method::adaptive:
      return "adaptive";
    default:
      return "compliant";
  }
}

// A run of `method` with its knob: delta_p / (m V), or the tolerance.
Outcome run(const Case& c, const chains::ChainModel& model, Method method, double knob) {
  switch (method) {
    case Method::impulse:
      return run_lzb(c, model, knob);
    case Method::adaptive:
      return run_adaptive(model, knob);
    default:
      return run_compliant(c, model, knob);
  }
}

void work_precision(benchmark::State& state, const Case* c, Method method, double knob) {
  const chains::ChainModel model = chains::build_chain_model(c->scene);
  const Outcome& exact = reference(*c, model);
  Outcome outcome;
  for (auto _ : state) {
    outcome = run(*c, model, method, knob);
    benchmark::DoNotOptimize(outcome.velocity.data());
  }
  state.counters["velocity_error"] = relative_error(outcome.velocity, exact.velocity);
  state.counters["force_error"] = relative_error(outcome.peak_force, exact.peak_force);
  state.counters["steps"] = double(outcome.steps);
  state.counters["knob"] = knob;
}

chains::ChainScene scene_file(const std::string& name) {
  return chains::load_chain_scene(MIMPACT_SOURCE_DIR "/examples/scenes/" + name);
}

// C1's beads and striker, `beads` long; the compliant run stops at `end_time` (s): behind the
// wave the beads of a long chain come to rest touching, so its contacts never all open.
chains::ChainScene c1_like_chain(int beads, double end_time) {
  chains::ChainScene scene = scene_file("c1.json");
  scene.chain.segments[0].count = beads;
  scene.compliant.end_time = end_time;
  return scene;
}

std::vector<Case> cases() {
  const std::vector<double> shares{1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6};
  std::vector<Case> all{
      {"C1", scene_file("c1.json"), 1e-12, shares},
      {"C2", scene_file("c2.json"), 1e-12, shares},
      {"N", scene_file("paper/nakagawa_e0955.json"), 0.0, shares},
      {"M2", scene_file("paper/melo_type2_q1.json"), 0.0, shares},
      // the wave leaves the last bead at 0.0297 s (LZB); 1e-5 of m V is already 22 M steps
      {"chain1000", c1_like_chain(1000, 0.032), 1e-10, {1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5}},
  };
  for (Case& c : all) c.scene.record = {};
  return all;
}

// The cost against the length: C1-like chains of n beads, the impulse steps at delta_p = 1e-4
// m V, the adaptive and compliant methods at tolerance 1e-6, each run until the wave has left:
// it forms within 2e-4 s and crosses a bead in 3e-5 s (LZB: 6.3e-4 s for 20 beads, 0.0297 s
// for 1 000).
void chain_length(benchmark::State& state, Method method, int beads) {
  Case c{"n", c1_like_chain(beads, 2e-4 + 3.2e-5 * beads), 0.0, {}};
  const chains::ChainModel model = chains::build_chain_model(c.scene);
  Outcome outcome;
  for (auto _ : state) {
    outcome = run(c, model, method, method == Method::impulse ? 1e-4 : 1e-6);
    benchmark::DoNotOptimize(outcome.velocity.data());
  }
  state.counters["beads"] = beads;
  state.counters["steps"] = double(outcome.steps);
  // the speed of the last bead, the wave's: both methods must have let it go
  state.counters["last_velocity"] = outcome.velocity(outcome.velocity.size() - 1);
}

std::string knob_text(double knob) {
  char text[32];
  std::snprintf(text, sizeof text, "%.0e", knob);
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  static const std::vector<Case> all = cases();
  const std::vector<double> tolerances{1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10};
  for (const Case& c : all)
    for (Method method : {Method::impulse, Method::adaptive, Method::compliant})
      for (double knob : method == Method::impulse ? c.shares : tolerances)
        if (method != Method::compliant || knob <= 1e-4)  // its loosest (CompliantSpec)
          benchmark::RegisterBenchmark(
              ("WorkPrecision/" + c.name + "/" + method_name(method) + "/" + knob_text(knob))
                  .c_str(),
              work_precision, &c, method, knob)
              ->Unit(benchmark::kMillisecond)
              ->UseRealTime();
  for (int beads : {10, 30, 100, 300, 1000, 3000, 10000, 30000, 100000})
    for (Method method : {Method::impulse, Method::adaptive, Method::compliant})
      benchmark::RegisterBenchmark(
          ("ChainLength/" + std::string(method_name(method)) + "/" + std::to_string(beads)).c_str(),
          chain_length, method, beads)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
