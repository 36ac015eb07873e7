#pragma once

#include <Eigen/Dense>
#include <string>
#include <string_view>

#include "mimpact/common/fields.hpp"

namespace mimpact::numerics {

// How a Lemke run ended. No "cycling": the lexicographic ratio test never revisits a basis.
enum class LemkeStatus {
  solved,           // z verifies: complementarity_error <= options.acceptance_tolerance
  ray_termination,  // the entering column had no positive entry: no solution was reached
  pivot_limit,      // options.max_pivots pivots made without termination
  invalid_input,    // M not square, sizes that disagree, or a non-finite entry
  inaccurate,       // the pivoting ended but z fails the verification even after polishing
};

std::string_view to_string(LemkeStatus status);

struct LemkeOptions {
  // Most pivots allowed; 0 means 1000 + 100 n (Lemke usually needs O(n)).
  int max_pivots = 0;
  // An entry of the entering column counts as positive when it exceeds this times the
  // column's largest magnitude.
  double pivot_tolerance = 1e-11;
  // Two ratios tie when they differ by less than this, relative to the ratio's scale.
  double ratio_tolerance = 1e-11;
  // A solution is accepted when its complementarity_error (lcp_problem.hpp) is at most this.
  double acceptance_tolerance = 1e-9;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("max_pivots", self.max_pivots, at_least(0, "0: 1000 + 100 n"));
    field("pivot_tolerance", self.pivot_tolerance, within(0.0, 1.0, {}, false, true));
    field("ratio_tolerance", self.ratio_tolerance, within(0.0, 1.0, {}, false, true));
    field("acceptance_tolerance", self.acceptance_tolerance, positive());
  }
};

struct LemkeResult {
  LemkeStatus status = LemkeStatus::invalid_input;
  Eigen::VectorXd z;                   // the complementary point reached (the solution when solved)
  Eigen::VectorXd w;                   // M z + q, from the original data
  int pivots = 0;                      // counting the entry and the exit of the artificial variable
  double complementarity_error = 0.0;  // lcp_problem.hpp, measured on the original data
  std::string message;                 // what went wrong, empty when solved

  bool solved() const { return status == LemkeStatus::solved; }
};

// Lemke's complementary pivoting method with covering vector d = (1, ..., 1) (Lemke 1965;
// Cottle, Pang & Stone, "The Linear Complementarity Problem", 1992, section 4.4).
// Degeneracy is resolved by the lexicographic minimum-ratio rule, with ties going to the
// artificial variable so the run ends as soon as it can; q >= 0 returns z = 0 at once.
// The final basis is re-solved on the original data (M_SS z_S = -q_S) and the more
// accurate of the two points is returned, with its verified complementarity error.
// Solves every LCP with a P-matrix, and every feasible one with a positive semidefinite
// (copositive-plus) matrix; ray termination otherwise.
LemkeResult solve_lemke(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                        const LemkeOptions& options = {});

}  // namespace mimpact::numerics
