#include "mimpact/analysis/lzb_tolerance_study.hpp"

#include <chrono>

#include "mimpact/common/error.hpp"

namespace mimpact::analysis {

namespace {

// The smallest tolerance the adaptive integrator accepts (LzbAdaptiveOptions).
constexpr double kSmallestTolerance = 1e-13;
constexpr double kReduction = 10.0;

struct Run {
  numerics::ImpactResult result;
  Eigen::VectorXd velocity_after;
  double wall_time = 0.0;
};

Run run(const ImpactProblemData& problem, numerics::LzbAdaptiveOptions options, double tolerance) {
  options.tolerance = tolerance;
  options.sample_interval = 0.0;
  numerics::LzbAdaptiveIntegrator integrator(options);
  Run measured;
  const auto start = std::chrono::steady_clock::now();
  measured.result = integrator.integrate(problem.H, problem.u_minus, problem.laws);
  measured.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (measured.result.status != numerics::ImpactStatus::terminated)
    throw Error("tolerance study: " + measured.result.message);
  measured.velocity_after = problem.velocity_before + problem.mobility * measured.result.impulse;
  return measured;
}

double relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const double scale = b.cwiseAbs().maxCoeff();
  const double gap = (a - b).cwiseAbs().maxCoeff();
  return scale > 0.0 ? gap / scale : gap;
}

ToleranceRow row_of(const Run& coarse, const Run& fine, double tolerance,
                    const ToleranceStudyOptions& options) {
  ToleranceRow row;
  row.tolerance = tolerance;
  row.steps = coarse.result.steps;
  row.wall_time = coarse.wall_time;
  row.eta_plus = relative(coarse.velocity_after, fine.velocity_after);
  row.peak_force_change = relative(coarse.result.max_force, fine.result.max_force);
  row.converged = row.eta_plus <= options.epsilon_plus && row.peak_force_change <= options.epsilon;
  return row;
}

}  // namespace

ToleranceStudy study_tolerance(const ImpactProblemData& problem,
                               const ToleranceStudyOptions& options) {
  validate(options, "tolerance study");
  ToleranceStudy study;
  double tolerance = options.first_tolerance;
  Run coarse = run(problem, options.integrator, tolerance);
  for (int k = 0; k < options.max_rows && tolerance / kReduction >= kSmallestTolerance;
       ++k, tolerance /= kReduction) {
    Run fine = run(problem, options.integrator, tolerance / kReduction);
    study.rows.push_back(row_of(coarse, fine, tolerance, options));
    study.finest_tolerance = tolerance / kReduction;
    study.finest = fine.result;
    study.finest_velocities = fine.velocity_after;
    if (study.rows.back().converged) {
      study.converged = true;
      break;
    }
    coarse = std::move(fine);
  }
  return study;
}

}  // namespace mimpact::analysis
