#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>

namespace mimpact::numerics {

// H = W^T M^-1 W, the Delassus operator that maps contact impulses to changes of the
// contact velocities (du = H dP), for a diagonal mass matrix given by its inverse.
// W is n_dof x n_contacts, column j the gradient of the gap of contact j. The result keeps
// the sparsity of W: a contact couples only with contacts sharing a body.
Eigen::SparseMatrix<double> assemble_delassus(const Eigen::SparseMatrix<double>& W,
                                              const Eigen::VectorXd& inverse_mass);

}  // namespace mimpact::numerics
