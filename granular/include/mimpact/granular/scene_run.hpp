#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "mimpact/granular/configuration_check.hpp"
#include "mimpact/granular/contact_model.hpp"
#include "mimpact/granular/error_estimate.hpp"
#include "mimpact/granular/impact_runs.hpp"
#include "mimpact/granular/progress_meter.hpp"
#include "mimpact/granular/run_limits.hpp"
#include "mimpact/granular/scene_spec.hpp"
#include "mimpact/granular/time_series.hpp"
#include "mimpact/kernel/non_smooth_dynamical_system.hpp"
#include "mimpact/numerics/impact_observer.hpp"
#include "mimpact/plugins/lzb_impact_options.hpp"

// One run of a granular scene by the method it chooses, whatever its geometry: what
// `mimpact chain`, `mimpact packing` and the Python module's run_chain() and run_packing() share.
// The chains and packings build the model and its kernel system; the run is this one.
namespace mimpact::granular {

// What the caller chooses beside the scene.
struct SceneRunOptions {
  ImpactOverrides impact;  // over the scene's "impact" (resolve_impact)
  bool record = true;      // sample the scene's "record"
  RunLimits limits;        // the memory the recording may take
  // Told where the run is, by each of its phases (the CLI's progress line).
  ProgressMeter* progress = nullptr;
  // A companion run of the scene at another step estimates the run's error (SceneRun's
  // error_estimate; docs/design/error_estimates.md).
  bool estimate_error = false;
};

// What the scene asks of its run: its fields common to every geometry.
struct SceneRunSpec {
  const plugins::LzbImpactOptions& impact;
  Method method = Method::lzb;
  const CompliantSpec& compliant;
  RecordSpec record;          // the contacts and bodies sampled
  int frame_every = 0;        // every this many samples, a frame of the whole scene (0: none)
  const std::string& source;  // the scene file, for messages
  // an LZB run of beads (model.beads) compares its frozen configuration with the moving geometry
  const ConfigurationCheckSpec* configuration_check = nullptr;
  // the scene's "accuracy": the run chooses its step to meet it (resolve_accuracy)
  std::optional<double> accuracy;
  // why the LZB method cannot run the scene, or empty: "method": "auto" takes the compliant
  // contacts then
  std::string lzb_unfit;
};

struct SceneRun {
  ImpactOutcome impact;
  Method method = Method::lzb;
  plugins::LzbImpactOptions options;  // the impact's options, as run
  CompliantSpec compliant;            // the compliant method's, as run
  std::optional<double> delta_p;      // N s, of the impulse steps; none for the other methods
  bool recorded = false;              // series (and frames, if asked for) hold the scene's record
  TimeSeries series;
  Frames frames;
  // the LZB run's frozen configuration against the beads as they move, when it was checked
  std::optional<ConfigurationCheck> configuration;
  MovingContactsStats moving;  // the work of a run in the moving geometry (zero otherwise)
  // when SceneRunOptions::estimate_error, or asked for an accuracy
  std::optional<ErrorEstimate> error_estimate;
  std::optional<AccuracyRun> accuracy;  // how the run met the accuracy it was asked for
  std::string why;                      // "method": "auto": the method chosen, and why

  // The answer is LZB's and its configuration check exceeds the accuracy: the scene needs the
  // compliant contacts (callers warn with configuration->describe()).
  bool configuration_fails() const {
    return method == Method::lzb && configuration && !configuration->holds();
  }
};

// A new kernel system of the model (body b is the model's body b), as the scene starts: a run
// takes one, its companion another.
using SystemFactory = std::function<std::shared_ptr<kernel::NonSmoothDynamicalSystem>()>;

// The LZB impacts (impulse steps at delta_p, or the adaptive integrator) through the
// event-driven scheme, or the compliant contacts integrated in time, as the scene says, on
// a system from `build_system`. An LZB run of beads is then checked against the
// moving geometry as spec.configuration_check says. "method": "auto" runs LZB, then the
// compliant contacts where its configuration check exceeds the accuracy (SceneRun::why). Asked
// for an accuracy, the run estimates
// its error and runs again at the step its estimate predicts until the estimate meets it (or
// the step rule's range ends: AccuracyRun::met). Throws InvalidInput for a missing or
// out-of-range delta_p, a delta_p given to another method or alongside relative_delta_p, and a
// recording beyond options.limits.
SceneRun run_scene(const ContactModel& model, const SystemFactory& build_system,
                   const SceneRunSpec& spec, const SceneRunOptions& options = {});

// The method of a run and its step, in words: "adaptive LZB, tolerance 1e-06".
std::string describe_method(const SceneRun& run);
// What the run chose and how sure it is, a line each: "method auto:" and why, the error
// estimate, how it met its accuracy ("" when it has none of them).
std::string describe_error(const SceneRun& run);

}  // namespace mimpact::granular
