#include "mimpact/numerics/lemke.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "mimpact/common/error.hpp"
#include "mimpact/numerics/lcp_problem.hpp"

namespace mimpact::numerics {

std::string_view to_string(LemkeStatus status) {
  switch (status) {
    case LemkeStatus::solved:
      return "solved";
    case LemkeStatus::ray_termination:
      return "ray_termination";
    case LemkeStatus::pivot_limit:
      return "pivot_limit";
    case LemkeStatus::invalid_input:
      return "invalid";
    case LemkeStatus::inaccurate:
      return "inaccurate";
  }
  return "unknown";
}

namespace {

using Eigen::Index;

// The augmented system w - M z - d z0 = q written in the current basis B:
// T = B^-1 [I | -M | -d | q]. Variables are numbered w_i = i, z_i = n + i, z0 = 2n, and the
// right-hand side is column 2n + 1. The w-columns of T hold B^-1, which the lexicographic
// rule compares.
class Tableau {
 public:
  Tableau(const Eigen::MatrixXd& M, const Eigen::VectorXd& q) : n_(q.size()) {
    table_.setZero(n_, 2 * n_ + 2);
    table_.leftCols(n_).setIdentity();
    table_.middleCols(n_, n_) = -M;
    table_.col(artificial()).setConstant(-1.0);
    table_.col(rhs_column()) = q;
    basis_.resize(n_);
    for (Index i = 0; i < n_; ++i) basis_[i] = i;
  }

  Index artificial() const { return 2 * n_; }
  Index complement(Index variable) const { return variable < n_ ? variable + n_ : variable - n_; }
  Index basic(Index row) const { return basis_[row]; }

  // Makes `entering` basic in `row`; returns the variable that leaves.
  Index pivot(Index row, Index entering) {
    Eigen::VectorXd column = table_.col(entering);
    table_.row(row) /= column(row);
    column(row) = 0.0;
    table_.noalias() -= column * table_.row(row);
    const Index leaving = basis_[row];
    basis_[row] = entering;
    return leaving;
  }

  // The row whose basic variable leaves when `entering` enters, or -1 when no entry of its
  // column is positive (ray termination). Lexicographic minimum ratio over the rows of
  // [rhs | B^-1], ties going first to the artificial variable.
  Index ratio_test(Index entering, const LemkeOptions& options) {
    const auto column = table_.col(entering);
    const double column_max = column.cwiseAbs().maxCoeff();
    candidates_.clear();
    for (Index i = 0; i < n_; ++i)
      if (column(i) > options.pivot_tolerance * column_max && column(i) > 0.0)
        candidates_.push_back(i);
    if (candidates_.empty()) return -1;

    keep_lexicographic_minimum(table_.col(rhs_column()), column, column_max, options);
    if (candidates_.size() > 1) {
      for (Index row : candidates_)
        if (basis_[row] == artificial()) return row;
    }
    for (Index k = 0; k < n_ && candidates_.size() > 1; ++k)
      keep_lexicographic_minimum(table_.col(k), column, column_max, options);
    return candidates_.front();
  }

  // Basic z values (z0 and w ignored); the point the basis describes.
  Eigen::VectorXd z() const {
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n_);
    for (Index row = 0; row < n_; ++row)
      if (basis_[row] >= n_ && basis_[row] < 2 * n_)
        z(basis_[row] - n_) = table_(row, rhs_column());
    return z;
  }

 private:
  Index rhs_column() const { return 2 * n_ + 1; }

  // Keeps the candidate rows whose ratio numerator(i) / column(i) is minimal up to the
  // tolerance. The tolerance scales with max|numerator| / max|column|, the size a ratio has
  // when nothing is small: a scale taken from the ratios themselves would let one tiny
  // pivot entry declare rows tied that are not, and the lexicographic order would be lost.
  void keep_lexicographic_minimum(const Eigen::Ref<const Eigen::VectorXd>& numerator,
                                  const Eigen::Ref<const Eigen::VectorXd>& column,
                                  double column_max, const LemkeOptions& options) {
    double minimum = INFINITY;
    for (Index row : candidates_) minimum = std::min(minimum, numerator(row) / column(row));
    const double scale = numerator.cwiseAbs().maxCoeff() / column_max;
    const double tie = options.ratio_tolerance * std::max(std::abs(minimum), scale);
    std::erase_if(candidates_,
                  [&](Index row) { return numerator(row) / column(row) > minimum + tie; });
  }

  Index n_;
  Eigen::MatrixXd table_;
  std::vector<Index> basis_;
  std::vector<Index> candidates_;
};

// Re-solves M_SS z_S = -q_S for the set S of positive z entries of `z` and keeps the
// result when it verifies better: the tableau's z carries the round-off of every pivot.
Eigen::VectorXd polish(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                       const Eigen::VectorXd& z) {
  std::vector<Index> support;
  for (Index i = 0; i < z.size(); ++i)
    if (z(i) > 0.0) support.push_back(i);
  if (support.empty()) return z;
  const Eigen::MatrixXd M_ss = M(support, support);
  const Eigen::VectorXd q_s = q(support);
  Eigen::FullPivLU<Eigen::MatrixXd> lu(M_ss);
  if (!lu.isInvertible()) return z;
  const Eigen::VectorXd z_s = lu.solve(-q_s);
  Eigen::VectorXd polished = Eigen::VectorXd::Zero(z.size());
  polished(support) = z_s;
  return complementarity_error(M, q, polished) < complementarity_error(M, q, z) ? polished : z;
}

void finish(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, Eigen::VectorXd z,
            LemkeResult& result) {
  result.z = polish(M, q, z);
  result.w = M * result.z + q;
  result.complementarity_error = complementarity_error(M, q, result.z);
}

}  // namespace

LemkeResult solve_lemke(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                        const LemkeOptions& options) {
  LemkeResult result;
  try {
    validate(options, "Lemke options");
    validate_lcp(M, q);
  } catch (const InvalidInput& error) {  // a result, as the other ways Lemke can end
    result.message = error.what();
    return result;
  }
  const Index n = q.size();
  if (n == 0 || q.minCoeff() >= 0.0) {
    result.status = LemkeStatus::solved;
    finish(M, q, Eigen::VectorXd::Zero(n), result);
    return result;
  }
  const int max_pivots = options.max_pivots > 0 ? options.max_pivots : 1000 + 100 * int(n);

  Tableau tableau(M, q);
  // z0 enters at the row of the most negative q; among equal q the last row, which is the
  // lexicographic choice for the columns of the identity.
  Index first_row = 0;
  for (Index i = 1; i < n; ++i)
    if (q(i) <= q(first_row)) first_row = i;
  Index entering = tableau.complement(tableau.pivot(first_row, tableau.artificial()));
  result.pivots = 1;

  while (true) {
    if (result.pivots >= max_pivots) {
      result.status = LemkeStatus::pivot_limit;
      std::ostringstream text;
      text << "no solution after " << result.pivots << " pivots (max_pivots = " << max_pivots
           << ")";
      result.message = text.str();
      finish(M, q, tableau.z(), result);
      return result;
    }
    const Index row = tableau.ratio_test(entering, options);
    if (row < 0) {
      // A ray; when z0 has already reached zero the basis still describes a solution.
      finish(M, q, tableau.z(), result);
      if (result.complementarity_error <= options.acceptance_tolerance) {
        result.status = LemkeStatus::solved;
      } else {
        result.status = LemkeStatus::ray_termination;
        result.message =
            "ray termination: the entering column has no positive entry "
            "(the LCP may have no solution)";
      }
      return result;
    }
    const Index leaving = tableau.pivot(row, entering);
    ++result.pivots;
    if (leaving == tableau.artificial()) break;
    entering = tableau.complement(leaving);
  }

  finish(M, q, tableau.z(), result);
  if (result.complementarity_error <= options.acceptance_tolerance) {
    result.status = LemkeStatus::solved;
  } else {
    result.status = LemkeStatus::inaccurate;
    std::ostringstream text;
    text << "the final basis gives complementarity error " << result.complementarity_error
         << " > acceptance_tolerance " << options.acceptance_tolerance;
    result.message = text.str();
  }
  return result;
}

}  // namespace mimpact::numerics
