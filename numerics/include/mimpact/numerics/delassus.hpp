#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>

namespace mimpact::numerics {

// The Delassus operator H = W^T M^-1 W, which maps contact impulses to changes of the contact
// velocities (du = H dP), with the mobility M^-1 W that maps them to changes of the
// generalized velocities (dv = M^-1 W dP). W is n_dof x n_contacts, column j the gradient of
// the gap of contact j; H keeps its sparsity (contacts couple only through shared bodies).
class Delassus {
 public:
  // A diagonal mass matrix, given by its inverse (0 for an immovable degree of freedom).
  Delassus(const Eigen::SparseMatrix<double>& W, const Eigen::VectorXd& inverse_mass);
  // A sparse symmetric positive definite mass matrix, factorized by CHOLMOD. Throws
  // InvalidInput when the factorization fails (M not positive definite).
  Delassus(const Eigen::SparseMatrix<double>& W, const Eigen::SparseMatrix<double>& mass);

  const Eigen::SparseMatrix<double>& H() const { return H_; }
  const Eigen::SparseMatrix<double>& mobility() const { return mobility_; }

 private:
  void assemble(const Eigen::SparseMatrix<double>& W);  // H from W and the mobility

  Eigen::SparseMatrix<double> H_;
  Eigen::SparseMatrix<double> mobility_;
};

// H alone, for a diagonal mass matrix given by its inverse.
Eigen::SparseMatrix<double> assemble_delassus(const Eigen::SparseMatrix<double>& W,
                                              const Eigen::VectorXd& inverse_mass);

}  // namespace mimpact::numerics
