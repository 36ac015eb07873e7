#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "mimpact/analysis/lzb_convergence.hpp"
#include "mimpact/analysis/lzb_tolerance_study.hpp"
#include "mimpact/chains/chain_model.hpp"
#include "mimpact/chains/chain_scene.hpp"

namespace mimpact::cli {

// The study that `converge` runs and `chain --tolerance` uses to choose delta_p. The first
// delta_p is `first` (the command line option `first_option`) when given, else the scene's,
// else 1e-3 of the natural impulse m V; `tolerance` holds eps+ and optionally eps (default
// 0.01 each, eps = eps+ when one is given). Throws InvalidInput for a compliant scene.
analysis::ConvergenceOptions convergence_options(
    const chains::ChainScene& scene, const chains::ChainModel& model, std::optional<double> first,
    const std::string& first_option, const std::vector<double>& tolerance, int max_halvings);

// Whether a requested accuracy is met by the adaptive integrator's tolerance study rather than
// by halving delta_p: the scene chose "integrator": "adaptive", or left both the integrator and
// delta_p unsaid. A scene that gives delta_p or "integrator": "impulse-step" keeps the seed's
// study.
bool uses_tolerance_study(const chains::ChainScene& scene);

// The tolerance study of an adaptive scene: the first tolerance is `first` when given, else
// the scene's impact.tolerance when it gives one, else the smallest of eps+ and eps (the
// error of a run is about its tolerance on short chains). `tolerance` as above.
analysis::ToleranceStudyOptions tolerance_study_options(const chains::ChainScene& scene,
                                                        std::optional<double> first,
                                                        const std::string& first_option,
                                                        const std::vector<double>& tolerance,
                                                        int max_rows);

// {"rows": [{"delta_p", "impulse_steps", "wall_time", "max_eta", "eta_plus", "converged"}],
//  "extrapolated_velocities": [...], "converged"}
nlohmann::ordered_json convergence_json(const analysis::ConvergenceStudy& study);

// {"rows": [{"tolerance", "steps", "wall_time", "eta_plus", "peak_force_change", "converged"}],
//  "finest_tolerance", "finest_velocities", "converged"}
nlohmann::ordered_json tolerance_json(const analysis::ToleranceStudy& study);

// The tolerance study's table and its finest velocities, to stdout.
void print_tolerance_table(const analysis::ToleranceStudy& study);

// The table of the paper's tables 2-4 and the extrapolated velocities, to stdout.
void print_convergence_table(const analysis::ConvergenceStudy& study);

}  // namespace mimpact::cli
