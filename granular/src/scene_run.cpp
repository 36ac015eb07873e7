#include "mimpact/granular/scene_run.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <future>
#include <limits>
#include <optional>
#include <stop_token>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "mimpact/common/error.hpp"
#include "mimpact/granular/error_estimate.hpp"
#include "mimpact/granular/impact_recorder.hpp"

namespace mimpact::granular {

namespace {

// The impulse steps state no accuracy of their own (first order in delta_p): unless the scene
// says otherwise, their configuration check warns above this share of the striker's speed.
constexpr double kImpulseStepAccuracy = 1e-3;

// Hands every sample to several observers.
class Observers : public numerics::ImpactObserver {
 public:
  void add(numerics::ImpactObserver* observer) {
    if (observer) observers_.push_back(observer);
  }
  void observe(const numerics::ImpactSample& sample) override {
    for (numerics::ImpactObserver* observer : observers_) observer->observe(sample);
  }
  void progressed(const numerics::ImpactProgress& where) override {
    for (numerics::ImpactObserver* observer : observers_) observer->progressed(where);
  }
  bool empty() const { return observers_.empty(); }

 private:
  std::vector<numerics::ImpactObserver*> observers_;
};

// Tells a progress meter where the LZB impact is.
class ProgressObserver : public numerics::ImpactObserver {
 public:
  explicit ProgressObserver(ProgressMeter* meter) : meter_(meter) {}
  void observe(const numerics::ImpactSample& sample) override {
    meter_->report(
        {.time = sample.time, .steps = sample.step, .impulse = sample.principal_impulse});
  }
  void progressed(const numerics::ImpactProgress& where) override {
    meter_->report({.time = where.time, .steps = where.step, .impulse = where.principal_impulse});
  }

 private:
  ProgressMeter* meter_;
};

SceneRun run_lzb(const ContactModel& model,
                 std::shared_ptr<kernel::NonSmoothDynamicalSystem> system, const SceneRunSpec& spec,
                 const SceneRunOptions& options, plugins::LzbImpactOptions impact, bool record) {
  SceneRun run;
  if (impact.chosen_integrator() != plugins::LzbIntegrator::adaptive) {
    const double delta_p = impulse_step(model, impact, impact_labels(options.impact));
    if (impact.delta_p) run.delta_p = delta_p;
  }
  ImpactRecorder recorder(model, spec.record, spec.frame_every, options.limits);
  Observers observers;
  if (record) {
    recorder.configure(impact);
    observers.add(&recorder);
  }
  ProgressObserver progress(options.progress);
  if (options.progress) {
    options.progress->begin("LZB impact");
    observers.add(&progress);
  }
  run.impact =
      simulate_impacts(model, std::move(system), impact, observers.empty() ? nullptr : &observers);
  if (record) {
    run.series = recorder.series(run.impact);
    run.frames = recorder.frames(run.impact);
  }
  run.recorded = record;
  run.options = impact;
  return run;
}

// The LZB run's frozen configuration against the moving geometry, when the spec asks for it;
// `accuracy` is the one its figure is compared with.
void check_frozen_configuration(SceneRun& run, const ContactModel& model, const SceneRunSpec& spec,
                                const SceneRunOptions& options, double accuracy) {
  const ConfigurationCheckSpec* check = spec.configuration_check;
  if (run.method != Method::lzb || !check || !check->enabled || !model.beads) return;
  run.configuration =
      check_configuration(model, run.impact, *check, accuracy, options.limits, options.progress);
}

SceneRun run_compliant(const ContactModel& model,
                       std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                       const SceneRunSpec& spec, const SceneRunOptions& options,
                       const CompliantSpec& compliant_spec, bool record) {
  if (options.progress)
    options.progress->begin("compliant contacts", compliant_spec.end_time.value_or(
                                                      std::numeric_limits<double>::quiet_NaN()));
  CompliantRun compliant = simulate_compliant(model, std::move(system), compliant_spec,
                                              {.record = record ? spec.record : RecordSpec{},
                                               .frame_every = record ? spec.frame_every : 0,
                                               .limits = options.limits,
                                               .progress = options.progress});
  SceneRun run;
  run.method = Method::compliant;
  run.impact = std::move(compliant.impact);
  run.series = std::move(compliant.series);
  run.frames = std::move(compliant.frames);
  run.moving = compliant.moving;
  run.recorded = record;
  return run;
}

// An LZB run stopped at its step limit (impact.max_steps) has no answer: within an accuracy's
// runs it spent its budget, as a compliant run past compliant.max_steps does.
void require_answer(const SceneRun& run) {
  if (run.impact.result.status == numerics::ImpactStatus::step_limit)
    throw BudgetSpent(run.impact.result.message, run.impact.result.duration);
}

// An accuracy's answer with its estimate, held while a finer run goes on: the answer again where
// that run spends its budget. Its record is not held beside the finer runs': it is sampled again.
struct HeldAnswer {
  HeldAnswer(SceneRun answer, const StepOptions& ran_with, const ErrorEstimate& its_estimate,
             double step_value)
      : run(std::move(answer)), options(ran_with), estimate(its_estimate), value(step_value) {
    run.series = {};
    run.frames = {};
    run.recorded = false;
  }
  SceneRun run;
  StepOptions options;  // as it ran
  ErrorEstimate estimate;
  double value;  // its step rule's
};

// What every run of a scene shares: the model, its systems, the spec and the caller's options.
struct SceneRuns {
  const ContactModel& model;
  const SystemFactory& build_system;
  const SceneRunSpec& spec;
  const SceneRunOptions& options;
  bool record = false;  // the answer's run samples the scene's record

  // The scene's run at the step options `step`, by its method, sampling its record if
  // `recorded` (the answer's run), told to `meter`.
  SceneRun at(const StepOptions& step, bool recorded, ProgressMeter* meter) const {
    SceneRunOptions told = options;
    told.progress = meter;
    SceneRun run = spec.method == Method::lzb
                       ? run_lzb(model, build_system(), spec, told, step.impact, recorded)
                       : run_compliant(model, build_system(), spec, told, step.compliant, recorded);
    run.compliant = step.compliant;
    return run;
  }
  SceneRun at(const StepOptions& step, bool recorded) const {
    return at(step, recorded, options.progress);
  }
  SceneRun at(const StepOptions& step) const { return at(step, record); }

  // The answer's run at `step` (sampling the record if `recorded`) and its companion's: side by
  // side when the limits allow two threads, else one after the other.
  std::pair<SceneRun, SceneRun> with_companion(const StepOptions& step, bool recorded,
                                               const Companion& companion) const {
    if (options.limits.threads >= 2) return side_by_side(step, recorded, companion);
    SceneRun run = at(step, recorded);
    return {std::move(run), at(companion.options, false)};
  }
  std::pair<SceneRun, SceneRun> side_by_side(const StepOptions& step, bool recorded,
                                             const Companion& companion) const;

  // The run at `step`, with its companion's estimate of its error.
  SceneRun estimated(const StepOptions& step) const {
    const Companion companion = companion_of(step_rule(model, spec.method, step), step);
    auto [run, other] = with_companion(step, record, companion);
    require_answer(other);
    run.error_estimate =
        estimate_error(model, run.impact.velocity_after, other.impact.velocity_after, companion);
    run.error_estimate->companion_seconds = other.impact.wall_time;
    return run;
  }

  SceneRun to_accuracy(StepOptions step, double accuracy) const;
  SceneRun with_coarser_companions(StepOptions step, StepRule rule, double accuracy) const;
  SceneRun with_finer_companions(StepOptions step, StepRule rule, double accuracy) const;
};

// The finer of the two runs on this thread, told to the caller's meter (the progress line shows
// the longer), the other on a second with a meter of its own (the same deadline, no line). As
// one after the other, the answer's failure is raised first: it stops the companion; the
// companion's failure is raised once the answer is done.
std::pair<SceneRun, SceneRun> SceneRuns::side_by_side(const StepOptions& step, bool recorded,
                                                      const Companion& companion) const {
  const bool answer_here = !companion.finer;
  std::stop_source stop_companion;
  const std::unique_ptr<ProgressMeter> there_meter = ProgressMeter::beside(
      options.progress, answer_here ? stop_companion.get_token() : std::stop_token());
  std::unique_ptr<ProgressMeter> own;  // this thread's, where the caller gave none
  ProgressMeter* here_meter = options.progress;
  if (!answer_here && here_meter)
    here_meter->stop_when(stop_companion.get_token());
  else if (!answer_here)
    here_meter = (own = ProgressMeter::beside(nullptr, stop_companion.get_token())).get();
  auto answer = [&](ProgressMeter* meter) { return at(step, recorded, meter); };
  auto other = [&](ProgressMeter* meter) { return at(companion.options, false, meter); };
  std::future<SceneRun> beside = std::async(std::launch::async, [&] {
    if (answer_here) return other(there_meter.get());
    try {
      return answer(there_meter.get());
    } catch (...) {
      stop_companion.request_stop();
      throw;
    }
  });
  if (answer_here) {
    SceneRun run;
    try {
      run = answer(here_meter);
    } catch (...) {
      stop_companion.request_stop();
      beside.wait();  // stopped, or done: not the caller's concern
      throw;
    }
    return {std::move(run), beside.get()};
  }
  std::optional<SceneRun> finer;
  std::exception_ptr failed;
  try {
    finer = other(here_meter);
  } catch (const RunStopped&) {  // the answer failed: its failure is raised below
  } catch (...) {
    failed = std::current_exception();
  }
  if (options.progress) options.progress->stop_when({});
  SceneRun run = beside.get();
  if (failed) std::rethrow_exception(failed);
  return {std::move(run), std::move(*finer)};
}

// Runs of the scene at finer and finer steps until one's estimate meets `accuracy`
// (docs/design/error_estimates.md, "Accuracy"): the answer is the last; at most kMostRuns.
constexpr int kMostRuns = 6;

SceneRun SceneRuns::to_accuracy(StepOptions step, double accuracy) const {
  step = first_step(model, spec.method, step, accuracy);
  const StepRule rule = step_rule(model, spec.method, step);
  SceneRun run = rule.companion > 1.0 ? with_coarser_companions(step, rule, accuracy)
                                      : with_finer_companions(step, rule, accuracy);
  run.accuracy->asked = accuracy;
  run.accuracy->met = run.error_estimate->worst <= accuracy;
  return run;
}

// Why an accuracy's runs end with the estimate above it ("" where they go on): the estimate is
// not finite, the step is at its finest, or the next run would pass kMostRuns.
std::string why_ended(double estimate, const StepRule& rule, bool runs_left) {
  if (!std::isfinite(estimate)) return "the estimate is not finite";
  if (rule.value <= rule.finest) return "the step's range ended, at its finest";
  if (!runs_left) return "the most runs, " + std::to_string(kMostRuns) + ", ended first";
  return "";
}

// delta_p: each run is the coarser companion of the next.
SceneRun SceneRuns::with_coarser_companions(StepOptions step, StepRule rule,
                                            double accuracy) const {
  SceneRun run = estimated(step);
  require_answer(run);
  ErrorEstimate estimate = *run.error_estimate;
  int runs = 2;
  std::string ended;
  while (estimate.worst > accuracy &&
         (ended = why_ended(estimate.worst, rule, runs + 1 <= kMostRuns)).empty()) {
    StepRule finer = rule;
    finer.value = next_step(rule, estimate.worst, accuracy, run.impact.result.steps);
    step = finer.at(step, finer.value);
    const double seconds = estimate.companion_seconds + run.impact.wall_time;
    const Eigen::VectorXd previous = std::move(run.impact.velocity_after);
    run = {};  // its recording is not held beside the next run's
    run = at(step);
    require_answer(run);
    estimate = estimate_error(model, run.impact.velocity_after, previous,
                              companion_at(finer, step, rule.value));
    estimate.companion_seconds = seconds;
    rule = finer;
    ++runs;
  }
  run.error_estimate = estimate;
  run.accuracy = AccuracyRun{.runs = runs, .step = rule.name, .value = rule.value, .ended = ended};
  return run;
}

// A tolerance: the run and its finer companion; while the estimate is above the accuracy, the
// companion becomes the run where the estimate is within kChainReach of the accuracy (the
// companion's own error about the estimate x its ratio of the step, 0.2), else a new pair starts
// at the step the estimate predicts, with the order observed from the run before. Companions sample
// no record: an answer that was one runs again to sample it (beyond kMostRuns). Where a finer run
// spends its budget of steps, the answer is the last one with an estimate, not met.
constexpr double kChainReach = 6.0;

SceneRun SceneRuns::with_finer_companions(StepOptions step, StepRule rule, double accuracy) const {
  std::optional<SceneRun> run;        // the answer's, at `step`, once made
  StepOptions answer_options = step;  // as the answer ran (a companion's: with its budget)
  double seconds = 0.0;               // of every run made
  int runs = 0;
  ErrorEstimate estimate;
  std::optional<std::pair<double, double>> pair_before;  // its step and estimate
  std::optional<HeldAnswer> held;  // the answer before, while a finer run goes on
  std::string ended;
  while (true) {
    const Companion companion = companion_of(rule, step);
    SceneRun finer;
    try {
      if (run) {
        ++runs;
        finer = at(companion.options, false);
      } else {
        runs += 2;
        std::tie(run, finer) = with_companion(step, record, companion);
        answer_options = step;
        require_answer(*run);
        seconds += run->impact.wall_time;
      }
      require_answer(finer);
    } catch (const BudgetSpent& spent) {
      if (!held) throw;  // the first pair's: no answer
      ended = "a run finer than " + rule.name + " " + to_text(held->value) +
              " spent its budget of steps: " + spent.what();
      run = std::move(held->run);
      answer_options = held->options;
      estimate = held->estimate;
      rule.value = held->value;
      break;
    }
    seconds += finer.impact.wall_time;
    estimate =
        estimate_error(model, run->impact.velocity_after, finer.impact.velocity_after, companion);
    const double finer_value = rule.value * rule.companion;  // the companion's, in range
    const bool chain = finer_value >= rule.finest && estimate.worst <= kChainReach * accuracy;
    if (estimate.worst <= accuracy ||
        !(ended = why_ended(estimate.worst, rule, runs + (chain ? 1 : 2) <= kMostRuns)).empty())
      break;
    const double order = pair_before ? observed_order(pair_before->first, pair_before->second,
                                                      rule.value, estimate.worst)
                                     : 1.0;
    const double next =
        chain ? finer_value
              : next_step(rule, estimate.worst, accuracy, run->impact.result.steps, order);
    pair_before = {rule.value, estimate.worst};
    held = HeldAnswer(std::move(*run), answer_options, estimate, rule.value);
    step = rule.at(step, next);
    rule.value = next;
    if (chain) {
      run = std::move(finer);
      answer_options = companion.options;
    } else {
      run.reset();
    }
  }
  if (!run->recorded && record) {
    run.reset();
    run = at(answer_options);
    seconds += run->impact.wall_time;
    ++runs;
  }
  estimate.companion_seconds = seconds - run->impact.wall_time;
  run->error_estimate = estimate;
  run->accuracy = AccuracyRun{.runs = runs, .step = rule.name, .value = rule.value, .ended = ended};
  return std::move(*run);
}

// The scene's run by spec.method, LZB or compliant.
SceneRun run_method(const ContactModel& model, const SystemFactory& build_system,
                    const SceneRunSpec& spec, const SceneRunOptions& options) {
  const SceneRuns runs{
      .model = model,
      .build_system = build_system,
      .spec = spec,
      .options = options,
      .record = options.record && (!spec.record.contacts.empty() || !spec.record.bodies.empty() ||
                                   spec.frame_every > 0)};
  const std::optional<double> accuracy = resolve_accuracy(spec.accuracy, options.impact);
  const StepOptions step{
      .impact = resolve_impact(spec.impact, spec.method, options.impact, spec.source, accuracy),
      .compliant = spec.compliant};
  SceneRun run = accuracy                 ? runs.to_accuracy(step, *accuracy)
                 : options.estimate_error ? runs.estimated(step)
                                          : runs.at(step);
  const bool adaptive = run.options.chosen_integrator() == plugins::LzbIntegrator::adaptive;
  check_frozen_configuration(run, model, spec, options,
                             accuracy   ? *accuracy
                             : adaptive ? run.options.adaptive_tolerance()
                                        : kImpulseStepAccuracy);
  return run;
}

// "method": "auto" with neither an accuracy nor a step rule asks for this one.
constexpr double kAutomaticAccuracy = 1e-3;

// "method": "auto": LZB where its frozen configuration is the beads' own (a chain) or within the
// accuracy of them (the configuration check), else the compliant contacts; SceneRun::why says
// which and why.
SceneRun run_automatic(const ContactModel& model, const SystemFactory& build_system,
                       const SceneRunSpec& spec, const SceneRunOptions& options) {
  SceneRunSpec chosen = spec;
  const plugins::LzbImpactOptions& impact = spec.impact;
  if (!resolve_accuracy(spec.accuracy, options.impact) && !options.impact.delta_p &&
      !impact.delta_p && !impact.relative_delta_p && !impact.tolerance)
    chosen.accuracy = kAutomaticAccuracy;
  const double accuracy =
      resolve_accuracy(chosen.accuracy, options.impact).value_or(kAutomaticAccuracy);
  char why[512];
  if (!spec.lzb_unfit.empty() || !spec.configuration_check || !model.beads) {
    chosen.method = spec.lzb_unfit.empty() ? Method::lzb : Method::compliant;
    SceneRun run = run_method(model, build_system, chosen, options);
    run.why = spec.lzb_unfit.empty()
                  ? "LZB: the contacts of a chain stay on its line, where LZB's frozen "
                    "configuration is the beads' own"
                  : "the compliant contacts: " + spec.lzb_unfit;
    return run;
  }
  ConfigurationCheckSpec check = *spec.configuration_check;
  check.enabled = true;
  check.accuracy = accuracy;
  chosen.configuration_check = &check;
  chosen.method = Method::lzb;
  SceneRun lzb = run_method(model, build_system, chosen, options);
  const ConfigurationCheck& configuration = *lzb.configuration;
  if (!configuration.not_made.empty()) {
    lzb.why = "LZB: the moving geometry could not check its frozen configuration (" +
              configuration.not_made + ")";
    return lzb;
  }
  std::snprintf(why, sizeof why,
                "the beads as they move part from LZB's frozen configuration by %.2g of the "
                "fastest speed at worst (the configuration check), %s the accuracy %.3g",
                configuration.worst_error, configuration.holds() ? "within" : "beyond", accuracy);
  if (configuration.holds()) {
    lzb.why = std::string("LZB: ") + why;
    return lzb;
  }
  chosen.method = Method::compliant;
  SceneRun compliant = run_method(model, build_system, chosen, options);
  compliant.configuration = lzb.configuration;
  compliant.why = std::string("the compliant contacts in the moving geometry: ") + why;
  return compliant;
}

}  // namespace

SceneRun run_scene(const ContactModel& model, const SystemFactory& build_system,
                   const SceneRunSpec& spec, const SceneRunOptions& options) {
  return spec.method == Method::automatic ? run_automatic(model, build_system, spec, options)
                                          : run_method(model, build_system, spec, options);
}

std::string describe_method(const SceneRun& run) {
  if (run.method == Method::compliant)
    return "compliant contacts integrated in time, tolerance " + to_text(run.compliant.tolerance);
  if (run.options.chosen_integrator() == plugins::LzbIntegrator::adaptive)
    return "adaptive LZB, tolerance " + to_text(run.options.adaptive_tolerance());
  if (run.delta_p) return "LZB impulse steps, delta_p = " + to_text(*run.delta_p) + " N s";
  return "LZB impulse steps, relative_delta_p = " +
         to_text(run.options.relative_delta_p.value_or(0.0));
}

std::string describe_error(const SceneRun& run) {
  std::string lines = run.why.empty() ? "" : "method auto: " + run.why + "\n";
  if (!run.error_estimate) return lines;
  const ErrorEstimate& estimate = *run.error_estimate;
  char text[512];
  std::snprintf(text, sizeof text,
                "error estimate: worst body %.2g, RMS %.2g of the fastest speed before the impact "
                "(%s; %.3g s)\n",
                estimate.worst, estimate.rms, estimate.method.c_str(), estimate.companion_seconds);
  std::string line = lines + text;
  if (run.accuracy) {
    std::snprintf(text, sizeof text, "accuracy %.3g %s in %d runs, %s %.3g", run.accuracy->asked,
                  run.accuracy->met ? "met" : "NOT met", run.accuracy->runs,
                  run.accuracy->step.c_str(), run.accuracy->value);
    line += text + (run.accuracy->met ? "" : ": " + run.accuracy->ended) + "\n";
  }
  return line;
}

}  // namespace mimpact::granular
