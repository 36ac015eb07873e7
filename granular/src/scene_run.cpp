#include "mimpact/granular/scene_run.hpp"

#include <chrono>
#include <limits>
#include <utility>
#include <vector>

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
  bool empty() const { return observers_.empty(); }

 private:
  std::vector<numerics::ImpactObserver*> observers_;
};

// Hands the LZB samples to a progress meter.
class ProgressObserver : public numerics::ImpactObserver {
 public:
  explicit ProgressObserver(ProgressMeter* meter) : meter_(meter) {}
  void observe(const numerics::ImpactSample& sample) override {
    meter_->report(
        {.time = sample.time, .steps = sample.step, .impulse = sample.principal_impulse});
  }

 private:
  ProgressMeter* meter_;
};

// Where the run samples nothing for its record, it samples for its progress line: the impulse
// steps every kProgressSteps steps, the adaptive integrator kProgressSamples times in the
// shortest impact the model may have; one contact each (the samples change no step).
constexpr std::int64_t kProgressSteps = 65'536;
constexpr double kProgressSamples = 4.0;

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
  } else if (options.progress) {
    impact.impulse_steps.sample_every = kProgressSteps;
    impact.impulse_steps.sampled_contacts = {0};
    if (impact.adaptive.sample_interval == 0.0)
      impact.adaptive.sample_interval = impact_duration_bound(model) / kProgressSamples;
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

// The LZB run, and its configuration against the moving geometry when the spec asks for it.
SceneRun run_lzb_checked(const ContactModel& model,
                         std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                         const SceneRunSpec& spec, const SceneRunOptions& options,
                         const plugins::LzbImpactOptions& impact, bool record) {
  SceneRun run = run_lzb(model, std::move(system), spec, options, impact, record);
  const ConfigurationCheckSpec* check = spec.configuration_check;
  if (check && check->enabled && model.beads) {
    const double accuracy = impact.chosen_integrator() == plugins::LzbIntegrator::adaptive
                                ? impact.adaptive_tolerance()
                                : kImpulseStepAccuracy;
    run.configuration =
        check_configuration(model, run.impact, *check, accuracy, options.limits, options.progress);
  }
  return run;
}

SceneRun run_compliant(const ContactModel& model,
                       std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                       const SceneRunSpec& spec, const SceneRunOptions& options, bool record) {
  if (options.progress)
    options.progress->begin("compliant contacts", spec.compliant.end_time.value_or(
                                                      std::numeric_limits<double>::quiet_NaN()));
  CompliantRun compliant = simulate_compliant(model, std::move(system), spec.compliant,
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

}  // namespace

SceneRun run_scene(const ContactModel& model, const SystemFactory& build_system,
                   const SceneRunSpec& spec, const SceneRunOptions& options) {
  const bool record = options.record && (!spec.record.contacts.empty() ||
                                         !spec.record.bodies.empty() || spec.frame_every > 0);
  const plugins::LzbImpactOptions impact =
      resolve_impact(spec.impact, spec.method, options.impact, spec.source);
  SceneRun run = spec.method == Method::lzb
                     ? run_lzb_checked(model, build_system(), spec, options, impact, record)
                     : run_compliant(model, build_system(), spec, options, record);
  if (options.estimate_error) {
    const Companion companion = companion_of(model, spec.method, impact, spec.compliant);
    const auto clock = std::chrono::steady_clock::now();
    const Eigen::VectorXd velocity =
        spec.method == Method::lzb
            ? simulate_impacts(model, build_system(), companion.impact).velocity_after
            : simulate_compliant(model, build_system(), companion.compliant).impact.velocity_after;
    run.error_estimate = estimate_error(model, run.impact.velocity_after, velocity, companion);
    run.error_estimate->companion_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
  }
  return run;
}

}  // namespace mimpact::granular
