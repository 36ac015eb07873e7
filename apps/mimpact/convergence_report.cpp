#include "convergence_report.hpp"

#include <cmath>
#include <cstdio>

#include "mimpact/common/error.hpp"

namespace mimpact::cli {

analysis::ConvergenceOptions convergence_options(
    const chains::ChainScene& scene, const chains::ChainModel& model, std::optional<double> first,
    const std::string& first_option, const std::vector<double>& tolerance, int max_halvings) {
  if (scene.method != chains::Method::lzb)
    throw InvalidInput(
        "the convergence study runs the LZB method over delta_p; the scene has method "
        "\"compliant\"");
  if (tolerance.size() > 2)
    throw InvalidInput("--tolerance takes eps+ and at most eps; got " +
                       std::to_string(tolerance.size()) + " values");
  analysis::ConvergenceOptions options;
  options.first_delta_p = first           ? *first
                          : scene.delta_p ? *scene.delta_p
                                          : 1e-3 * chains::natural_impulse(model);
  chains::check_delta_p(model, options.first_delta_p,
                        scene.impact_options().impulse_steps.max_steps,
                        first ? first_option : "impact.delta_p");
  const char* names[] = {"--tolerance eps+", "--tolerance eps"};
  for (std::size_t k = 0; k < tolerance.size(); ++k)
    if (!(tolerance[k] > 0.0 && std::isfinite(tolerance[k])))
      throw InvalidInput(invalid_value_message(names[k], tolerance[k], "a finite value > 0"));
  if (max_halvings < 1)
    throw InvalidInput(invalid_value_message("--halvings", max_halvings, "an integer >= 1"));
  if (!tolerance.empty()) options.epsilon_plus = options.epsilon = tolerance[0];
  if (tolerance.size() == 2) options.epsilon = tolerance[1];
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
          {"converged", study.converged}};
}

void print_convergence_table(const analysis::ConvergenceStudy& study) {
  std::printf("%12s %10s %10s %10s %10s %10s\n", "delta_p", "steps", "time (s)", "max eta_h",
              "eta+_h", "converged");
  for (const analysis::ConvergenceRow& row : study.rows)
    std::printf("%12.4g %10lld %10.3g %10.3g %10.3g %10s\n", row.delta_p, (long long)row.steps,
                row.wall_time, row.max_eta, row.eta_plus, row.converged ? "yes" : "no");
  const Eigen::VectorXd& v = study.extrapolated_velocities;
  std::printf("Richardson-extrapolated post-impact velocities (m/s):");
  for (Eigen::Index i = 0; i < v.size(); ++i)
    std::printf("%s%.6g", i % 7 == 0 ? "\n  " : " ", v(i));
  std::printf("\n%s\n", study.converged ? "converged" : "not converged within the halvings");
}

}  // namespace mimpact::cli
