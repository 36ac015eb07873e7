// The cost of asking for an accuracy (issue 48, docs/accuracy.md): for each scene of the error
// corpus (tests/data/error_corpus/corpus.json) by its method and accuracy 1e-4, 1e-6 and 1e-8,
// the run asked for it, its companions included, against the cheapest single step that would
// have met it, known in hindsight: of the steps a quarter decade apart from a hundred times
// coarser than the one the run chose to ten times finer, the coarsest whose worst body is within
// the accuracy of the same scene 10 000 times finer than the run's step (the impulse steps: of
// their limit, the adaptive LZB at 1e-4 of the accuracy). Each time is the least of as many
// repeats as fit in half a second.
//
// Counters: ratio (the run's wall-clock time over the hindsight step's; the run's companions
// beside it on a second core, RunLimits::threads), cpu_ratio (the same with the processor time of
// every thread), ratio_to_estimated and cpu_ratio_to_estimated (over the hindsight step's run
// with its own error estimate, as a run of that step reports it by default), runs (the answer's and
// its companions'), met (the estimate within the accuracy), estimate and truth (worst body, of the
// striker's speed), step (the answer's delta_p in N s or tolerance) and hindsight_step. An accuracy
// whose impulse steps would pass impact.max_steps is refused by the run: skipped here. A run that
// did not meet its accuracy counts as an infinite ratio. The last lines: the median ratios, per
// accuracy and over all.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <string>
#include <vector>

#include "../tests/support/error_corpus.hpp"
#include "mimpact/common/error.hpp"

namespace {

using namespace mimpact;
using testing::CorpusCase;
using testing::CorpusScene;

// The ratios of each accuracy: to the hindsight step's bare run (wall-clock and processor time),
// and to its run with its estimate.
struct Ratios {
  std::vector<double> bare, cpu, estimated, cpu_estimated;
};
std::map<double, Ratios>& ratios() {
  static std::map<double, Ratios> by_accuracy;
  return by_accuracy;
}

// Wall-clock and processor time (s, of every thread of the process).
struct Seconds {
  double wall = INFINITY, cpu = INFINITY;
};

// The least times of `run` over as many repeats as fit in kRepeatSeconds (at least one).
constexpr double kRepeatSeconds = 0.5;
template <class Run>
Seconds least_seconds(const Run& run) {
  Seconds least;
  double spent = 0.0;
  do {
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t cpu_start = std::clock();
    run();
    const double cpu = double(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    least = {std::min(least.wall, seconds), std::min(least.cpu, cpu)};
    spent += seconds;
  } while (spent + least.wall < kRepeatSeconds);
  return least;
}

bool compliant(const nlohmann::json& scene) { return scene.value("method", "lzb") == "compliant"; }

// At 1e-8 the impulse steps take 1e8 steps and more (most are refused by impact.max_steps): their
// limit, the adaptive LZB, is the method there; the benchmark leaves them out.
bool impulse_steps(const nlohmann::json& scene) {
  return !compliant(scene) &&
         scene.value("impact", nlohmann::json::object()).value("integrator", "") != "adaptive";
}

// The scene with its step rule replaced by "accuracy" (the impulse steps kept as its method).
nlohmann::json asking(nlohmann::json scene, double accuracy) {
  if (compliant(scene)) {
    scene["compliant"].erase("tolerance");
  } else {
    nlohmann::json& impact = scene["impact"];
    if (impact.value("integrator", "") != "adaptive") impact["integrator"] = "impulse-step";
    for (const char* field : {"delta_p", "relative_delta_p", "tolerance"}) impact.erase(field);
  }
  scene["accuracy"] = accuracy;
  return scene;
}

// The scene at a single step: `field` "delta_p" (N s) or "tolerance" at `value`.
nlohmann::json at_step(nlohmann::json scene, const std::string& field, double value) {
  scene.erase("accuracy");
  if (compliant(scene))
    scene["compliant"]["tolerance"] = value;
  else
    scene["impact"][field] = value;
  return scene;
}

struct Hindsight {
  Seconds seconds;            // the fastest single step's that met the accuracy
  Seconds estimated_seconds;  // the same step's run with its error estimate
  double step = 0.0;
};

// The cheapest single step near `chosen` whose worst body is within `accuracy` of `exact`: the
// coarsest that meets it, a quarter decade at a time from a hundred times coarser down.
Hindsight hindsight(const CorpusScene& entry, const granular::AccuracyRun& chosen,
                    const Eigen::VectorXd& exact, const granular::ContactModel& model) {
  for (int quarter = 8; quarter >= -4; --quarter) {
    const double step = chosen.value * std::pow(10.0, quarter / 4.0);
    try {
      const CorpusCase single =
          testing::prepare_corpus_scene(at_step(entry.scene, chosen.step, step), entry.name);
      granular::SceneRun run = single.run({.record = false});
      if (testing::error_against(model, run.impact.velocity_after, exact).worst > chosen.asked)
        continue;
      return {least_seconds([&] { run = single.run({.record = false}); }),
              least_seconds([&] { run = single.run({.record = false, .estimate_error = true}); }),
              step};
    } catch (const InvalidInput&) {  // beyond the step's range, or its max_steps
    } catch (const BudgetSpent&) {   // a step past the budget of its scene's run
    }
  }
  return {};
}

void accuracy_cost(benchmark::State& state, const CorpusScene* entry, double accuracy) {
  CorpusCase asked;
  granular::SceneRun run;
  Seconds seconds;
  try {
    asked = testing::prepare_corpus_scene(asking(entry->scene, accuracy), entry->name);
    for (auto _ : state) {
      seconds = least_seconds([&] { run = asked.run({.record = false}); });
      state.SetIterationTime(seconds.wall);
    }
  } catch (const InvalidInput& refused) {
    state.SkipWithError(refused.what());
    return;
  }
  const granular::AccuracyRun& chosen = *run.accuracy;
  nlohmann::json finest = at_step(entry->scene, chosen.step, chosen.value / 10.0);
  const nlohmann::json reference = testing::finer_by_1000(finest, 1e-4 * accuracy);
  Eigen::VectorXd exact;
  try {
    exact = testing::run_corpus_scene(reference, entry->name, {.record = false})
                .run.impact.velocity_after;
  } catch (const Error& beyond) {  // the run took the finest step there is, or its budget
    state.SkipWithError((std::string("no reference 10 000 times finer: ") + beyond.what()).c_str());
    return;
  }
  const Hindsight best = hindsight(*entry, chosen, exact, *asked.model);
  // a run that did not meet its accuracy failed, whatever its time: it counts as infinite
  const double failed = chosen.met ? 1.0 : INFINITY;
  const double ratio = failed * seconds.wall / best.seconds.wall;
  const double cpu_ratio = failed * seconds.cpu / best.seconds.cpu;
  const double to_estimated = failed * seconds.wall / best.estimated_seconds.wall;
  const double cpu_to_estimated = failed * seconds.cpu / best.estimated_seconds.cpu;
  if (std::isfinite(best.seconds.wall)) {  // else no single step within the range met it
    ratios()[accuracy].bare.push_back(ratio);
    ratios()[accuracy].cpu.push_back(cpu_ratio);
    ratios()[accuracy].estimated.push_back(to_estimated);
    ratios()[accuracy].cpu_estimated.push_back(cpu_to_estimated);
  }
  state.counters["ratio"] = ratio;
  state.counters["cpu_ratio"] = cpu_ratio;
  state.counters["ratio_to_estimated"] = to_estimated;
  state.counters["cpu_ratio_to_estimated"] = cpu_to_estimated;
  state.counters["runs"] = chosen.runs;
  state.counters["met"] = chosen.met;
  state.counters["estimate"] = run.error_estimate->worst;
  state.counters["truth"] =
      testing::error_against(*asked.model, run.impact.velocity_after, exact).worst;
  state.counters["step"] = chosen.value;
  state.counters["hindsight_step"] = best.step;
}

double median(std::vector<double> values) {
  if (values.empty()) return NAN;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  static const std::vector<CorpusScene> corpus = testing::error_corpus(MIMPACT_SOURCE_DIR);
  for (const CorpusScene& entry : corpus)
    for (double accuracy : {1e-4, 1e-6, 1e-8}) {
      if (accuracy < 1e-6 && impulse_steps(entry.scene)) continue;
      char name[160];
      std::snprintf(name, sizeof name, "Accuracy/%s/%.0e", entry.name.c_str(), accuracy);
      benchmark::RegisterBenchmark(name, accuracy_cost, &entry, accuracy)
          ->Iterations(1)
          ->UseManualTime()
          ->Unit(benchmark::kMillisecond);
    }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  Ratios all;
  for (const auto& [accuracy, values] : ratios()) {
    std::printf(
        "median ratio at accuracy %.0e: %.3g (processor time: %.3g; to the estimated run: %.3g, "
        "processor time %.3g) over %zu scenes\n",
        accuracy, median(values.bare), median(values.cpu), median(values.estimated),
        median(values.cpu_estimated), values.bare.size());
    all.bare.insert(all.bare.end(), values.bare.begin(), values.bare.end());
    all.cpu.insert(all.cpu.end(), values.cpu.begin(), values.cpu.end());
    all.estimated.insert(all.estimated.end(), values.estimated.begin(), values.estimated.end());
    all.cpu_estimated.insert(all.cpu_estimated.end(), values.cpu_estimated.begin(),
                             values.cpu_estimated.end());
  }
  std::printf(
      "median ratio over all: %.3g (processor time: %.3g; to the estimated run: %.3g, processor "
      "time %.3g) over %zu runs\n",
      median(all.bare), median(all.cpu), median(all.estimated), median(all.cpu_estimated),
      all.bare.size());
  return 0;
}
