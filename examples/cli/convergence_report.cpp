#include "convergence_report.hpp"

#include <cstdio>

#include "mimpact/numerics/error.hpp"

namespace mimpact::cli {

numerics::ConvergenceOptions convergence_options(const chain::ChainScene& scene,
                                                 const chain::ChainModel& model,
                                                 std::optional<double> first,
                                                 const std::string& first_option,
                                                 const std::vector<double>& tolerance,
                                                 int max_halvings) {
  if (scene.method != chain::Method::lzb)
    throw InvalidInput("the convergence study runs the LZB method over delta_p; the scene has method "
                       "\"compliant\"");
  if (tolerance.size() > 2)
    throw InvalidInput("--tolerance takes eps+ and at most eps; got " + std::to_string(tolerance.size()) +
                       " values");
  numerics::ConvergenceOptions options;
  options.first_delta_p = first ? *first : scene.delta_p ? *scene.delta_p : 1e-3 * chain::natural_impulse(model);
  chain::check_delta_p(model, options.first_delta_p, options.integrator.max_steps,
                       first ? first_option : "impact.delta_p");
  if (!tolerance.empty()) options.epsilon_plus = options.epsilon = tolerance[0];
  if (tolerance.size() == 2) options.epsilon = tolerance[1];
  options.max_halvings = max_halvings;
  options.integrator = scene.lzb_options(options.first_delta_p);
  options.check();
  return options;
}

nlohmann::ordered_json convergence_json(const numerics::ConvergenceStudy& study) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const numerics::ConvergenceRow& row : study.rows)
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

void print_convergence_table(const numerics::ConvergenceStudy& study) {
  std::printf("%12s %10s %10s %10s %10s %10s\n", "delta_p", "steps", "time (s)", "max eta_h", "eta+_h",
              "converged");
  for (const numerics::ConvergenceRow& row : study.rows)
    std::printf("%12.4g %10lld %10.3g %10.3g %10.3g %10s\n", row.delta_p, (long long)row.steps,
                row.wall_time, row.max_eta, row.eta_plus, row.converged ? "yes" : "no");
  const Eigen::VectorXd& v = study.extrapolated_velocities;
  std::printf("Richardson-extrapolated post-impact velocities (m/s):");
  for (Eigen::Index i = 0; i < v.size(); ++i) std::printf("%s%.6g", i % 7 == 0 ? "\n  " : " ", v(i));
  std::printf("\n%s\n", study.converged ? "converged" : "not converged within the halvings");
}

}  // namespace mimpact::cli
