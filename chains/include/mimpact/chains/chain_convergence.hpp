#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "mimpact/analysis/lzb_convergence.hpp"
#include "mimpact/analysis/lzb_tolerance_study.hpp"
#include "mimpact/chains/chain_model.hpp"
#include "mimpact/chains/chain_scene.hpp"
#include "mimpact/granular/run_limits.hpp"

// The convergence studies of a chain scene's LZB impact, as `mimpact converge`, `mimpact chain
// --tolerance` and the Python module's converge() ask for them.
namespace mimpact::chains {

// What a study is asked: the accuracy, where it starts and how many rows it may take, with the
// names the error messages give them (command-line options, or Python keywords).
struct StudyRequest {
  std::vector<double> tolerance;  // eps+ and optionally eps; default 0.01 each
  std::optional<double> first;    // the first delta_p (N s) or the first tolerance
  int max_rows = 12;
  std::string tolerance_name = "--tolerance";
  std::string first_name = "--from";
  std::string rows_name = "--halvings";
  granular::RunLimits limits;  // the memory the runs' samples may take
};

// Whether a requested accuracy is met by the adaptive integrator's tolerance study rather than
// by halving delta_p: the scene chose "integrator": "adaptive", or left both the integrator and
// delta_p unsaid. A scene that gives delta_p or "integrator": "impulse-step" keeps the seed's
// study.
bool uses_tolerance_study(const ChainScene& scene);

// The tolerance study of an adaptive scene: the first tolerance is request.first when given,
// else the scene's impact.tolerance when it gives one, else the smallest of eps+ and eps (the
// error of a run is about its tolerance on short chains). Throws InvalidInput for a compliant
// scene or a value out of range, naming it.
analysis::ToleranceStudyOptions tolerance_study_options(const ChainScene& scene,
                                                        const StudyRequest& request);

// The step-halving study (Nguyen & Brogliato 2011, appendix A.2): the first delta_p is
// request.first when given, else the scene's, else 1e-3 of the natural impulse m V.
analysis::ConvergenceOptions convergence_options(const ChainScene& scene, const ChainModel& model,
                                                 const StudyRequest& request);

// {"rows": [{"delta_p", "impulse_steps", "wall_time", "max_eta", "eta_plus", "converged"}],
//  "extrapolated_velocities": [...], "converged", "stopped"}
nlohmann::ordered_json convergence_json(const analysis::ConvergenceStudy& study);

// {"rows": [{"tolerance", "steps", "wall_time", "eta_plus", "peak_force_change", "converged"}],
//  "finest_tolerance", "finest_velocities", "converged"}
nlohmann::ordered_json tolerance_json(const analysis::ToleranceStudy& study);

// The study the scene calls for (uses_tolerance_study), run, as the JSON above with "study":
// "tolerance" or "delta_p" first.
nlohmann::ordered_json study_chain_convergence(const ChainScene& scene, const ChainModel& model,
                                               const StudyRequest& request);

}  // namespace mimpact::chains
