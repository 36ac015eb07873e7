#include "convergence_report.hpp"

#include <cstdio>

namespace mimpact::cli {

namespace {

// One number per entry, seven to a line, under `title`.
void print_velocities(const char* title, const Eigen::VectorXd& v) {
  std::printf("%s", title);
  for (Eigen::Index i = 0; i < v.size(); ++i)
    std::printf("%s%.6g", i % 7 == 0 ? "\n  " : " ", v(i));
  std::printf("\n");
}

}  // namespace

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
