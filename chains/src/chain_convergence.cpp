#include "mimpact/chains/chain_convergence.hpp"

#include <algorithm>
#include <cmath>

#include "mimpact/chains/chain_impact.hpp"
#include "mimpact/common/error.hpp"

namespace mimpact::chains {

namespace {

// eps+ and eps from the request into `epsilon_plus` and `epsilon`.
void read_tolerance(const StudyRequest& request, double& epsilon_plus, double& epsilon) {
  const std::vector<double>& tolerance = request.tolerance;
  if (tolerance.size() > 2)
    throw InvalidInput(request.tolerance_name + " takes eps+ and at most eps; got " +
                       std::to_string(tolerance.size()) + " values");
  for (std::size_t k = 0; k < tolerance.size(); ++k)
    if (!(tolerance[k] > 0.0 && std::isfinite(tolerance[k])))
      throw InvalidInput(invalid_value_message(request.tolerance_name + (k == 0 ? " eps+" : " eps"),
                                               tolerance[k], "a finite value > 0"));
  if (!tolerance.empty()) epsilon_plus = epsilon = tolerance[0];
  if (tolerance.size() == 2) epsilon = tolerance[1];
}

void check_rows(const StudyRequest& request) {
  if (request.max_rows < 1)
    throw InvalidInput(
        invalid_value_message(request.rows_name, request.max_rows, "an integer >= 1"));
}

void check_lzb(const ChainScene& scene) {
  if (scene.method != granular::Method::lzb)
    throw InvalidInput(
        "the convergence study runs the LZB method over delta_p or its tolerance; the scene has "
        "method \"" +
        std::string(enum_name(scene.method)) + "\"");
}

}  // namespace

bool uses_tolerance_study(const ChainScene& scene) {
  return scene.adaptive() || (scene.method == granular::Method::lzb && !scene.impact.delta_p &&
                              !scene.impact.relative_delta_p && !scene.impact.integrator);
}

analysis::ToleranceStudyOptions tolerance_study_options(const ChainScene& scene,
                                                        const StudyRequest& request) {
  check_lzb(scene);
  analysis::ToleranceStudyOptions options;
  read_tolerance(request, options.epsilon_plus, options.epsilon);
  check_rows(request);
  options.max_rows = request.max_rows;
  options.integrator = scene.impact.adaptive_options();
  const bool scene_tolerance = scene.impact.tolerance.has_value();
  options.first_tolerance = request.first     ? *request.first
                            : scene_tolerance ? options.integrator.tolerance
                                              : std::min(options.epsilon_plus, options.epsilon);
  if (!fields::admits(within(1e-12, 0.1), options.first_tolerance, false))
    throw InvalidInput(invalid_value_message(
        request.first ? request.first_name
                      : (scene_tolerance ? "impact.tolerance" : request.tolerance_name),
        options.first_tolerance,
        "1e-12 <= first tolerance <= 0.1 (the study also runs a tenth of it, and double "
        "precision cannot meet a tolerance below 1e-13)"));
  validate(options, "tolerance study");
  return options;
}

analysis::ConvergenceOptions convergence_options(const ChainScene& scene, const ChainModel& model,
                                                 const StudyRequest& request) {
  check_lzb(scene);
  analysis::ConvergenceOptions options;
  const plugins::LzbImpactOptions& impact = scene.impact;
  options.first_delta_p = request.first    ? *request.first
                          : impact.delta_p ? *impact.delta_p
                          : impact.relative_delta_p
                              ? *impact.relative_delta_p * granular::natural_impulse(model)
                              : 1e-3 * granular::smallest_momentum(model);
  granular::check_delta_p(model, options.first_delta_p, impact.impulse_steps.max_steps,
                          request.first ? request.first_name : "impact.delta_p");
  read_tolerance(request, options.epsilon_plus, options.epsilon);
  check_rows(request);
  options.max_halvings = request.max_rows;
  options.integrator = impact.impulse_step_options();
  options.integrator.delta_p = options.first_delta_p;
  options.max_sample_bytes = request.limits.memory_bytes();
  validate(options, "convergence study");
  return options;
}

nlohmann::ordered_json convergence_json(const analysis::ConvergenceStudy& study) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const analysis::ConvergenceRow& row : study.rows)
    rows.push_back({{"delta_p", row.delta_p},
                    {"impulse_steps", row.steps},
                    {"wall_time", row.wall_time},
                    {"max_eta", row.max_eta},
                    {"eta_plus", row.eta_plus},
                    {"converged", row.converged}});
  const Eigen::VectorXd& v = study.extrapolated_velocities;
  return {{"rows", rows},
          {"extrapolated_velocities", std::vector<double>(v.data(), v.data() + v.size())},
          {"converged", study.converged},
          {"stopped", study.stopped}};
}

nlohmann::ordered_json tolerance_json(const analysis::ToleranceStudy& study) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const analysis::ToleranceRow& row : study.rows)
    rows.push_back({{"tolerance", row.tolerance},
                    {"steps", row.steps},
                    {"wall_time", row.wall_time},
                    {"eta_plus", row.eta_plus},
                    {"peak_force_change", row.peak_force_change},
                    {"converged", row.converged}});
  const Eigen::VectorXd& v = study.finest_velocities;
  return {{"rows", rows},
          {"finest_tolerance", study.finest_tolerance},
          {"finest_velocities", std::vector<double>(v.data(), v.data() + v.size())},
          {"converged", study.converged}};
}

nlohmann::ordered_json study_chain_convergence(const ChainScene& scene, const ChainModel& model,
                                               const StudyRequest& request) {
  nlohmann::ordered_json study;
  if (uses_tolerance_study(scene)) {
    study["study"] = "tolerance";
    study.update(tolerance_json(
        analysis::study_tolerance(impact_problem(model), tolerance_study_options(scene, request))));
  } else {
    study["study"] = "delta_p";
    study.update(convergence_json(analysis::study_convergence(
        impact_problem(model), convergence_options(scene, model, request))));
  }
  return study;
}

}  // namespace mimpact::chains
