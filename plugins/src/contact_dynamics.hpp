#pragma once

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <span>
#include <vector>

#include "mimpact/kernel/non_smooth_dynamical_system.hpp"
#include "mimpact/plugins/internal/mass_block.hpp"

namespace mimpact::plugins {

using kernel::Index;
using kernel::MatrixXd;
using kernel::VectorXd;

// The smooth dynamics of the system with a set S of contacts held closed:
//   M q'' = F + W_S lambda,   g''_S = W_S^T q'' + (dW_S/dt)^T v = H lambda + b,
// H = W_S^T M^-1 W_S, b = W_S^T M^-1 F + (dW_S/dt)^T v (Nguyen & Brogliato 2011, eqs. 21-26). Mass
// factorizations, W_S and H are kept while the set is unchanged and neither the mass nor
// the geometry depends on q, so that a right-hand side then allocates nothing. Systems of at
// most kDenseUpTo coordinates (a pendulum cradle, a rocking block) keep these matrices dense:
// for a handful of bodies the sparse products' bookkeeping costs several times the arithmetic,
// and nonlinear relations rebuild them at every right-hand side.
class ContactDynamics {
 public:
  void initialize(const kernel::NonSmoothDynamicalSystem& system);

  // Evaluates the free acceleration M^-1 F and, for the set S, H and b at (t, q, v).
  void evaluate(double t, const VectorXd& q, const VectorXd& v, std::span<const Index> set);

  const VectorXd& free_acceleration() const { return free_acceleration_; }
  const VectorXd& b() const { return b_; }
  // H = W_S^T M^-1 W_S for the set last evaluated, dense (the LCP solvers' input).
  MatrixXd H() const { return dense_ ? small_.H : MatrixXd(sparse_.H); }
  // The forces that keep every contact of S closed (g''_S = 0): H lambda = -b.
  const VectorXd& bilateral_force();
  // Solves H x = rhs for the set last evaluated (LDL^T, kept while H is).
  const VectorXd& solve(const VectorXd& rhs);
  // q'' = M^-1 (F + W_S lambda).
  void acceleration(const VectorXd& lambda, VectorXd& out) const;
  // x := M^-1 x, block by block (the masses as factorized by the last evaluate()).
  void apply_inverse_mass(VectorXd& x) const;
  // out += M^-1 W_S x: the velocity change of impulses x at the set's contacts.
  void add_mobility_times(const VectorXd& x, VectorXd& out) const;

  static constexpr Index kDenseUpTo = 64;

 private:
  void factorize_masses(const VectorXd& q);
  void assemble_inverse_mass();
  void assemble_set(const VectorXd& q, std::span<const Index> set);
  void assemble_dense_set(const VectorXd& q, std::span<const Index> set);
  void assemble_sparse_set(const VectorXd& q, std::span<const Index> set);
  void factorize_H();

  const kernel::NonSmoothDynamicalSystem* system_ = nullptr;
  std::vector<internal::MassBlock> blocks_;
  bool geometry_constant_ = true;  // every relation linear
  bool dense_ = false;             // at most kDenseUpTo coordinates
  VectorXd free_acceleration_, b_, lambda_;
  std::vector<Index> set_;  // the set H was assembled for
  bool set_valid_ = false, factor_valid_ = false, inverse_mass_valid_ = false;
  // M^-1, W_S, M^-1 W_S, H and its factorization, sparse or (dense_) dense
  struct SparseMatrices {
    Eigen::SparseMatrix<double> W, inverse_mass, mobility, H;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
    // the sparsity pattern of H that ldlt was analyzed (ordered) for
    bool pattern_analyzed = false;
    std::vector<int> analyzed_outer, analyzed_inner;
  };
  struct DenseMatrices {
    MatrixXd inverse_mass, W, mobility, H;
    Eigen::LDLT<MatrixXd> ldlt;
  };
  SparseMatrices sparse_;
  DenseMatrices small_;
};

}  // namespace mimpact::plugins
