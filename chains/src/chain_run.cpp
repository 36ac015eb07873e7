#include "mimpact/chains/chain_run.hpp"

#include <vector>

#include "mimpact/common/error.hpp"

namespace mimpact::chains {

namespace {

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

ChainRun run_lzb(const ChainScene& scene, const ChainModel& model, const ChainRunOptions& options,
                 plugins::LzbImpactOptions impact, bool record) {
  ChainRun run;
  if (!scene.adaptive()) {
    const double delta_p =
        granular::impulse_step(model, impact, granular::impact_labels(options.impact));
    if (impact.delta_p) run.delta_p = delta_p;
  }
  granular::ImpactRecorder recorder(model, scene.record, 0, options.limits);
  Observers observers;
  if (record) {
    recorder.configure(impact);
    observers.add(&recorder);
  } else if (options.progress) {
    impact.impulse_steps.sample_every = options.progress_every;
    impact.impulse_steps.sampled_contacts = {0};
  }
  observers.add(options.progress);
  run.impact = simulate_chain_impact(model, impact, observers.empty() ? nullptr : &observers);
  if (record) run.series = recorder.series(run.impact);
  run.recorded = record;
  run.options = impact;
  return run;
}

}  // namespace

ChainRun run_chain_scene(const ChainScene& scene, const ChainModel& model,
                         const ChainRunOptions& options) {
  const bool record =
      options.record && (!scene.record.contacts.empty() || !scene.record.bodies.empty());
  const plugins::LzbImpactOptions impact =
      granular::resolve_impact(scene.impact, scene.method, options.impact, scene.source);
  if (scene.method == granular::Method::lzb) return run_lzb(scene, model, options, impact, record);
  granular::CompliantRun compliant = granular::simulate_compliant(
      model, build_chain_system(model), scene.compliant,
      record ? scene.record : granular::RecordSpec{}, 0, options.limits);
  ChainRun run;
  run.method = granular::Method::compliant;
  run.impact = std::move(compliant.impact);
  run.series = std::move(compliant.series);
  run.recorded = record;
  return run;
}

nlohmann::ordered_json run_summary(const ChainModel& model, const ChainRun& run) {
  nlohmann::ordered_json summary =
      chain_summary(model, run.impact, run.delta_p, run.recorded ? &run.series : nullptr);
  summary["method"] = std::string(enum_name(run.method));
  if (run.method != granular::Method::lzb) return summary;
  summary["integrator"] = std::string(enum_name(run.options.chosen_integrator()));
  if (run.options.relative_delta_p) summary["relative_delta_p"] = *run.options.relative_delta_p;
  if (run.options.chosen_integrator() == plugins::LzbIntegrator::adaptive)
    summary["tolerance"] = run.options.adaptive_tolerance();
  return summary;
}

}  // namespace mimpact::chains
