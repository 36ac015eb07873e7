#include "mimpact/numerics/delassus.hpp"

#include <cmath>
#include <string>

#include "mimpact/numerics/error.hpp"

namespace mimpact::numerics {

Eigen::SparseMatrix<double> assemble_delassus(const Eigen::SparseMatrix<double>& W,
                                              const Eigen::VectorXd& inverse_mass) {
  if (inverse_mass.size() != W.rows())
    throw InvalidInput("inverse_mass has " + std::to_string(inverse_mass.size()) +
                       " entries but W has " + std::to_string(W.rows()) +
                       " rows; allowed: one entry per degree of freedom");
  for (Eigen::Index i = 0; i < inverse_mass.size(); ++i)
    if (!(inverse_mass(i) >= 0.0 && std::isfinite(inverse_mass(i))))
      throw InvalidInput(invalid_value_message("inverse_mass(" + std::to_string(i) + ")",
                                               inverse_mass(i), "a finite value >= 0 (1/kg)"));
  Eigen::SparseMatrix<double> H = W.transpose() * inverse_mass.asDiagonal() * W;
  H.makeCompressed();
  return H;
}

}  // namespace mimpact::numerics
