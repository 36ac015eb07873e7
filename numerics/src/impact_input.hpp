#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <span>

#include "mimpact/numerics/contact_law.hpp"

namespace mimpact::numerics {

// The checks of an impact's input shared by the LZB integrators: H square, finite and
// symmetric with a positive diagonal, one finite pre-impact velocity and one valid law per
// contact, at least one contact approaching, sampled contacts within range. Each failure
// throws InvalidInput naming the entry, its value and what is allowed. Returns diag(H).
Eigen::VectorXd checked_impact_input(const Eigen::SparseMatrix<double>& H,
                                     const Eigen::VectorXd& u_minus,
                                     std::span<const ContactLaw> laws,
                                     std::span<const Eigen::Index> sampled_contacts);
Eigen::VectorXd checked_impact_input(const Eigen::MatrixXd& H, const Eigen::VectorXd& u_minus,
                                     std::span<const ContactLaw> laws,
                                     std::span<const Eigen::Index> sampled_contacts);

}  // namespace mimpact::numerics
