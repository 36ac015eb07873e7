#include "convergence_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "mimpact/common/error.hpp"

namespace mimpact::cli {

namespace {

// eps+ and eps from --tolerance into `epsilon_plus` and `epsilon`.
void read_tolerance(const std::vector<double>& tolerance, double& epsilon_plus, double& epsilon) {
  if (tolerance.size() > 2)
    throw InvalidInput("--tolerance takes eps+ and at most eps; got " +
                       std::to_string(tolerance.size()) + " values");
  const char* names[] = {"--tolerance eps+", "--tolerance eps"};
  for (std::size_t k = 0; k < tolerance.size(); ++k)
    if (!(tolerance[k] > 0.0 && std::isfinite(tolerance[k])))
      throw InvalidInput(invalid_value_message(names[k], tolerance[k], "a finite value > 0"));
  if (!tolerance.empty()) epsilon_plus = epsilon = tolerance[0];
  if (tolerance.size() == 2) epsilon = tolerance[1];
}

void check_rows(int max_rows) {
  if (max_rows < 1)
    throw InvalidInput(invalid_value_message("--halvings", max_rows, "an integer >= 1"));
}

void check_lzb(const chains::ChainScene& scene) {
  if (scene.method != chains::Method::lzb)
    throw InvalidInput(
        "the convergence study runs the LZB method over delta_p or its tolerance; the scene has "
        "method \"compliant\"");
}

// One number per entry, seven to a line, under `title`.
void print_velocities(const char* title, const Eigen::VectorXd& v) {
  std::printf("%s", title);
  for (Eigen::Index i = 0; i < v.size(); ++i)
    std::printf("%s%.6g", i % 7 == 0 ? "\n  " : " ", v(i));
  std::printf("\n");
}

}  // namespace

bool uses_tolerance_study(const chains::ChainScene& scene) {
  return scene.adaptive() || (scene.method == chains::Method::lzb && !scene.delta_p &&
                              !scene.impact.contains("integrator"));
}

analysis::ToleranceStudyOptions tolerance_study_options(const chains::ChainScene& scene,
                                                        std::optional<double> first,
                                                        const std::string& first_option,
                                                        const std::vector<double>& tolerance,
                                                        int max_rows) {
  check_lzb(scene);
  analysis::ToleranceStudyOptions options;
  read_tolerance(tolerance, options.epsilon_plus, options.epsilon);
  check_rows(max_rows);
  options.max_rows = max_rows;
  options.integrator = scene.impact_options().adaptive_options();
  const bool scene_tolerance = scene.impact.contains("tolerance");
  options.first_tolerance = first             ? *first
                            : scene_tolerance ? options.integrator.tolerance
                                              : std::min(options.epsilon_plus, options.epsilon);
  if (!fields::admits(within(1e-12, 0.1), options.first_tolerance, false))
    throw InvalidInput(invalid_value_message(
        first ? first_option : (scene_tolerance ? "impact.tolerance" : "--tolerance"),
        options.first_tolerance,
        "1e-12 <= first tolerance <= 0.1 (the study also runs a tenth of it, and double "
        "precision cannot meet a tolerance below 1e-13)"));
  validate(options, "tolerance study");
  return options;
}

analysis::ConvergenceOptions convergence_options(
    const chains::ChainScene& scene, const chains::ChainModel& model, std::optional<double> first,
    const std::string& first_option, const std::vector<double>& tolerance, int max_halvings) {
  check_lzb(scene);
  analysis::ConvergenceOptions options;
  options.first_delta_p = first           ? *first
                          : scene.delta_p ? *scene.delta_p
                                          : 1e-3 * chains::natural_impulse(model);
  chains::check_delta_p(model, options.first_delta_p,
                        scene.impact_options().impulse_steps.max_steps,
                        first ? first_option : "impact.delta_p");
  read_tolerance(tolerance, options.epsilon_plus, options.epsilon);
  check_rows(max_halvings);
  options.max_halvings = max_halvings;
  options.integrator = scene.lzb_options(options.first_delta_p);
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

void print_convergence_table(const analysis::ConvergenceStudy& study) {
  std::printf("%12s %10s %10s %10s %10s %10s\n", "delta_p", "steps", "time (s)", "max eta_h",
              "eta+_h", "converged");
  for (const analysis::ConvergenceRow& row : study.rows)
    std::printf("%12.4g %10lld %10.3g %10.3g %10.3g %10s\n", row.delta_p, (long long)row.steps,
                row.wall_time, row.max_eta, row.eta_plus, row.converged ? "yes" : "no");
  print_velocities("Richardson-extrapolated post-impact velocities (m/s):",
                   study.extrapolated_velocities);
  if (!study.stopped.empty())
    std::printf("not converged: %s\n", study.stopped.c_str());
  else
    std::printf("%s\n", study.converged ? "converged" : "not converged within the halvings");
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

void print_tolerance_table(const analysis::ToleranceStudy& study) {
  std::printf("%12s %10s %10s %10s %12s %10s\n", "tolerance", "steps", "time (s)", "eta+",
              "peak force", "converged");
  for (const analysis::ToleranceRow& row : study.rows)
    std::printf("%12.4g %10lld %10.3g %10.3g %12.3g %10s\n", row.tolerance, (long long)row.steps,
                row.wall_time, row.eta_plus, row.peak_force_change, row.converged ? "yes" : "no");
  char title[96];
  std::snprintf(title, sizeof title,
                "post-impact velocities at tolerance %.3g (m/s):", study.finest_tolerance);
  print_velocities(title, study.finest_velocities);
  std::printf("%s\n", study.converged ? "converged" : "not converged within the rows");
}

}  // namespace mimpact::cli
