#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "mimpact/chains/chain_impact.hpp"
#include "mimpact/chains/chain_model.hpp"
#include "mimpact/chains/chain_scene.hpp"
#include "mimpact/granular/impact_recorder.hpp"
#include "mimpact/granular/run_limits.hpp"

// One run of a chain scene by the method it chooses: what `mimpact chain` and the Python
// module's run_chain() share.
namespace mimpact::chains {

struct ChainRunOptions {
  granular::ImpactOverrides impact;  // over the scene's "impact" (resolve_impact)
  bool record = true;                // sample the scene's "record" series
  granular::RunLimits limits;        // the memory the model and the recording may take
  // Sees the LZB samples too, at least every progress_every impulse steps (a progress report).
  numerics::ImpactObserver* progress = nullptr;
  std::int64_t progress_every = 2'000'000;
};

struct ChainRun {
  granular::ImpactOutcome impact;
  granular::Method method = granular::Method::lzb;
  plugins::LzbImpactOptions options;  // the impact's options, as resolved
  std::optional<double> delta_p;      // N s, of the impulse steps; none for the other methods
  bool recorded = false;              // series holds the scene's "record"
  granular::TimeSeries series;
};

// The LZB impact (impulse steps at delta_p, or the adaptive integrator) or the compliant
// method, as the scene says, with the overrides of options.impact. Throws InvalidInput when the
// impulse steps have no delta_p or one out of range, and for a delta_p given to another method
// or alongside relative_delta_p.
ChainRun run_chain_scene(const ChainScene& scene, const ChainModel& model,
                         const ChainRunOptions& options = {});

// summary.json of the run (chain_summary) with how it was computed: "method", and the impulse
// steps' delta_p or relative_delta_p, or the adaptive integrator's tolerance.
nlohmann::ordered_json run_summary(const ChainModel& model, const ChainRun& run);

}  // namespace mimpact::chains
