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
                 bool record) {
  ChainRun run;
  plugins::LzbImpactOptions impact = scene.impact_options();
  if (!scene.adaptive()) {
    run.delta_p = impulse_step(model, options.delta_p, scene.delta_p,
                               impact.impulse_steps.max_steps, options.delta_p_field);
    impact.impulse_steps = scene.lzb_options(*run.delta_p);
  }
  ImpactRecorder recorder(model, scene.record);
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
  return run;
}

}  // namespace

ChainRun run_chain_scene(const ChainScene& scene, const ChainModel& model,
                         const ChainRunOptions& options) {
  const bool record =
      options.record && (!scene.record.contacts.empty() || !scene.record.bodies.empty());
  if (scene.method == Method::lzb) return run_lzb(scene, model, options, record);
  if (options.delta_p)
    throw InvalidInput(options.delta_p_field +
                       " is the step of the LZB method; the scene has method \"compliant\"");
  CompliantRun compliant = simulate_chain_compliant(model, scene.compliant, scene.record);
  ChainRun run;
  run.impact = std::move(compliant.impact);
  run.series = std::move(compliant.series);
  run.recorded = record;
  return run;
}

}  // namespace mimpact::chains
