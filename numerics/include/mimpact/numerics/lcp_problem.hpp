#pragma once

#include <Eigen/Dense>
#include <string>

namespace mimpact::numerics {

// The linear complementarity problem LCP(M, q): find z with
//   z >= 0,  w = M z + q >= 0,  z^T w = 0.
struct LcpProblem {
  Eigen::MatrixXd M;
  Eigen::VectorXd q;
};

// Throws InvalidInput unless M is square, q has its size and every entry is finite, saying
// which is wrong and how.
void validate_lcp(const Eigen::MatrixXd& M, const Eigen::VectorXd& q);

// ||min(z, M z + q)||_inf relative to the size of the terms of w, max(||q||_inf,
// ||M||_inf ||z||_inf): zero exactly at a solution, and unchanged when the data are scaled.
// The natural-map residual catches a negative z, a negative w and a pair both positive.
// Infinite when z, w or the scale leave double precision: such a point verifies nothing.
double complementarity_error(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                             const Eigen::VectorXd& z);

}  // namespace mimpact::numerics
