#include "mimpact/numerics/lcp_problem.hpp"

#include <sstream>

#include "mimpact/common/error.hpp"

namespace mimpact::numerics {

void validate_lcp(const Eigen::MatrixXd& M, const Eigen::VectorXd& q) {
  std::ostringstream why;
  if (M.rows() != M.cols()) {
    why << "M is " << M.rows() << "x" << M.cols() << "; allowed: a square matrix";
  } else if (q.size() != M.rows()) {
    why << "q has " << q.size() << " entries; allowed: " << M.rows() << " (the size of M)";
  } else if (!M.allFinite()) {
    why << "M has a NaN or infinite entry; allowed: finite values";
  } else if (!q.allFinite()) {
    why << "q has a NaN or infinite entry; allowed: finite values";
  }
  if (!why.str().empty()) throw InvalidInput(why.str());
}

double complementarity_error(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                             const Eigen::VectorXd& z) {
  if (q.size() == 0) return 0.0;
  const Eigen::VectorXd w = M * z + q;
  // a point beyond double precision verifies nothing: its comparisons would pass with NaN
  if (!z.allFinite() || !w.allFinite()) return INFINITY;
  const double residual = z.cwiseMin(w).cwiseAbs().maxCoeff();
  const double matrix_norm = M.cwiseAbs().rowwise().sum().maxCoeff();
  const double scale = std::max(q.cwiseAbs().maxCoeff(), matrix_norm * z.cwiseAbs().maxCoeff());
  if (!std::isfinite(scale)) return INFINITY;
  if (scale == 0.0) return residual;
  return residual / scale;
}

}  // namespace mimpact::numerics
