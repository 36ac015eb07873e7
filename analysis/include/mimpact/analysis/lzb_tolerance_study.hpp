#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "mimpact/analysis/lzb_convergence.hpp"
#include "mimpact/numerics/lzb_adaptive_integrator.hpp"

namespace mimpact::analysis {

// The adaptive LZB integrator's counterpart of the step-size study: runs at tolerance t and
// t / 10 compared. Its error is proportional to t (docs/model.md, section 10), so the change
// from t to t / 10 bounds the error of the run at t, and the run at t / 10 is ten times closer.
struct ToleranceRow {
  double tolerance = 0.0;
  std::int64_t steps = 0;          // Runge-Kutta steps of the run at `tolerance`
  double wall_time = 0.0;          // s, of the run at `tolerance`
  double eta_plus = 0.0;           // ||v+_t - v+_(t/10)||_inf / ||v+_(t/10)||_inf
  double peak_force_change = 0.0;  // max_j |F_j,max(t) - F_j,max(t/10)| / max_j F_j,max(t/10)
  bool converged = false;          // eta_plus <= epsilon_plus and peak_force_change <= epsilon
};

struct ToleranceStudy {
  std::vector<ToleranceRow> rows;
  double finest_tolerance = 0.0;      // t / 10 of the last row
  numerics::ImpactResult finest;      // the run at finest_tolerance
  Eigen::VectorXd finest_velocities;  // its generalized post-impact velocities
  bool converged = false;
};

struct ToleranceStudyOptions {
  double first_tolerance = 1e-4;  // t of the first row
  double epsilon_plus = 0.01;     // bound on eta_plus
  double epsilon = 0.01;          // bound on peak_force_change
  int max_rows = 8;               // rows at most; a row below the smallest tolerance ends it
  numerics::LzbAdaptiveOptions integrator;  // every run's options but the tolerance

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("first_tolerance", self.first_tolerance, within(1e-12, 0.1));
    field("epsilon_plus", self.epsilon_plus, positive());
    field("epsilon", self.epsilon, positive());
    field("max_rows", self.max_rows, at_least(1));
    field("integrator", self.integrator);
  }
};

// Runs t, t / 10, t / 100, ... and fills a row per t from its run and the next; stops at the
// first t that meets both bounds, after max_rows rows, or when t / 10 would fall below the
// smallest tolerance double precision can meet (1e-13; the study is then not converged).
ToleranceStudy study_tolerance(const ImpactProblemData& problem,
                               const ToleranceStudyOptions& options);

}  // namespace mimpact::analysis
