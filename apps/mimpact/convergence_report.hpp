#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "mimpact/analysis/lzb_convergence.hpp"
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

// {"rows": [{"delta_p", "impulse_steps", "wall_time", "max_eta", "eta_plus", "converged"}],
//  "extrapolated_velocities": [...], "converged"}
nlohmann::ordered_json convergence_json(const analysis::ConvergenceStudy& study);

// The table of the paper's tables 2-4 and the extrapolated velocities, to stdout.
void print_convergence_table(const analysis::ConvergenceStudy& study);

}  // namespace mimpact::cli
