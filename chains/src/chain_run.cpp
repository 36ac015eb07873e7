#include "mimpact/chains/chain_run.hpp"

#include "mimpact/common/error.hpp"

namespace mimpact::chains {

granular::SceneRun run_chain_scene(const ChainScene& scene, const ChainModel& model,
                                   const granular::SceneRunOptions& options) {
  return granular::run_scene(
      model, [&] { return build_chain_system(model); },
      {.impact = scene.impact,
       .method = scene.method,
       .compliant = scene.compliant,
       .record = scene.record,
       .frame_every = 0,
       .source = scene.source,
       .accuracy = scene.accuracy,
       .lzb_unfit =
           scene.precompression > 0.0
               ? "a precompressed chain: the LZB impact starts from beads that barely touch"
               : ""},
      options);
}

nlohmann::ordered_json run_summary(const ChainModel& model, const granular::SceneRun& run) {
  nlohmann::ordered_json summary =
      chain_summary(model, run.impact, run.delta_p, run.recorded ? &run.series : nullptr);
  summary["method"] = std::string(enum_name(run.method));
  if (!run.why.empty()) summary["method_choice"] = run.why;
  if (run.error_estimate)
    summary["error_estimate"] = granular::error_estimate_json(run.error_estimate);
  if (run.accuracy) summary["accuracy"] = granular::accuracy_json(*run.accuracy);
  if (run.method != granular::Method::lzb) {
    summary["tolerance"] = run.compliant.tolerance;
    return summary;
  }
  summary["integrator"] = std::string(enum_name(run.options.chosen_integrator()));
  if (run.options.relative_delta_p) summary["relative_delta_p"] = *run.options.relative_delta_p;
  if (run.options.chosen_integrator() == plugins::LzbIntegrator::adaptive)
    summary["tolerance"] = run.options.adaptive_tolerance();
  return summary;
}

}  // namespace mimpact::chains
