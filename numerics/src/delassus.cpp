#include "mimpact/numerics/delassus.hpp"

#include <Eigen/CholmodSupport>
#include <cmath>
#include <string>

#include "mimpact/common/error.hpp"

namespace mimpact::numerics {

namespace {

void check_sizes(const Eigen::SparseMatrix<double>& W, Eigen::Index mass_size) {
  if (mass_size != W.rows())
    throw InvalidInput("the mass has " + std::to_string(mass_size) +
                       " degrees of freedom but W has " + std::to_string(W.rows()) +
                       " rows; allowed: one row per degree of freedom");
}

}  // namespace

Delassus::Delassus(const Eigen::SparseMatrix<double>& W, const Eigen::VectorXd& inverse_mass) {
  check_sizes(W, inverse_mass.size());
  for (Eigen::Index i = 0; i < inverse_mass.size(); ++i)
    if (!(inverse_mass(i) >= 0.0 && std::isfinite(inverse_mass(i))))
      throw InvalidInput(invalid_value_message("inverse_mass(" + std::to_string(i) + ")",
                                               inverse_mass(i), "a finite value >= 0 (1/kg)"));
  mobility_ = inverse_mass.asDiagonal() * W;
  assemble(W);
}

Delassus::Delassus(const Eigen::SparseMatrix<double>& W, const Eigen::SparseMatrix<double>& mass) {
  check_sizes(W, mass.rows());
  Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>> cholesky(mass);
  if (cholesky.info() != Eigen::Success)
    throw InvalidInput(
        "the mass matrix is not symmetric positive definite (CHOLMOD could not "
        "factorize it); allowed: positive masses");
  mobility_ = cholesky.solve(W);
  assemble(W);
}

void Delassus::assemble(const Eigen::SparseMatrix<double>& W) {
  H_ = W.transpose() * mobility_;
  // contacts whose directions are orthogonal at a shared body (a square packing's row and
  // column) do not couple: no entry, so that the impact integrators never visit the pair
  H_.prune(0.0);
  H_.makeCompressed();
}

Eigen::SparseMatrix<double> assemble_delassus(const Eigen::SparseMatrix<double>& W,
                                              const Eigen::VectorXd& inverse_mass) {
  return Delassus(W, inverse_mass).H();
}

}  // namespace mimpact::numerics
