#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "mimpact/chains/chain_impact.hpp"
#include "mimpact/chains/chain_model.hpp"
#include "mimpact/chains/chain_scene.hpp"
#include "mimpact/chains/impact_recorder.hpp"

// One run of a chain scene by the method it chooses: what `mimpact chain` and the Python
// module's run_chain() share.
namespace mimpact::chains {

struct ChainRunOptions {
  std::optional<double> delta_p;                 // N s: overrides the scene's (impulse steps)
  std::string delta_p_field = "impact.delta_p";  // what the messages about delta_p call it
  bool record = true;                            // sample the scene's "record" series
  // Sees the LZB samples too, at least every progress_every impulse steps (a progress report).
  numerics::ImpactObserver* progress = nullptr;
  std::int64_t progress_every = 2'000'000;
};

struct ChainRun {
  ImpactOutcome impact;
  std::optional<double> delta_p;  // N s, of the impulse steps; none for the other methods
  bool recorded = false;          // series holds the scene's "record"
  TimeSeries series;
};

// The LZB impact (impulse steps at delta_p, or the adaptive integrator) or the compliant
// method, as the scene says. Throws InvalidInput when the impulse steps have no delta_p or
// one out of range, and for a delta_p given to another method.
ChainRun run_chain_scene(const ChainScene& scene, const ChainModel& model,
                         const ChainRunOptions& options = {});

}  // namespace mimpact::chains
