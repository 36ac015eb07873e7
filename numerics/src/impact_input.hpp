#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <span>
#include <string_view>

#include "mimpact/numerics/contact_law.hpp"
#include "mimpact/numerics/tangential_rows.hpp"

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

// The friction of an impact: each law's friction finite and >= 0, and > 0 only for a contact
// with tangential rows and an integrator that integrates friction; the rows (when given) sized
// for the contacts, finite, H_tt symmetric with a positive diagonal. Throws InvalidInput naming
// the entry, its value and what is allowed.
void checked_friction(std::span<const ContactLaw> laws, const TangentialRows* rows,
                      bool integrates_friction, std::string_view integrator);

}  // namespace mimpact::numerics
