#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "mimpact/chains/chain_impact.hpp"
#include "mimpact/chains/chain_model.hpp"
#include "mimpact/chains/chain_scene.hpp"
#include "mimpact/granular/impact_recorder.hpp"
#include "mimpact/granular/run_limits.hpp"
#include "mimpact/granular/scene_run.hpp"

// One run of a chain scene by the method it chooses (granular::run_scene on the chain's model
// and system): what `mimpact chain` and the Python module's run_chain() share.
namespace mimpact::chains {

// The LZB impact (impulse steps at delta_p, or the adaptive integrator) or the compliant
// method, as the scene says, with the overrides of options.impact. Throws InvalidInput when the
// impulse steps have no delta_p or one out of range, and for a delta_p given to another method
// or alongside relative_delta_p.
granular::SceneRun run_chain_scene(const ChainScene& scene, const ChainModel& model,
                                   const granular::SceneRunOptions& options = {});

// summary.json of the run (chain_summary) with how it was computed: "method", and the impulse
// steps' delta_p or relative_delta_p, or the adaptive integrator's tolerance.
nlohmann::ordered_json run_summary(const ChainModel& model, const granular::SceneRun& run);

}  // namespace mimpact::chains
