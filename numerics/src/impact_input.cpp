#include "impact_input.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "mimpact/common/error.hpp"

namespace mimpact::numerics {

using Eigen::Index;

namespace {

std::string entry(Index i, Index j) {
  return "H(" + std::to_string(i) + ", " + std::to_string(j) + ")";
}

void check_entry(Index i, Index j, double h_ij, double h_ji, double scale) {
  if (!std::isfinite(h_ij))
    throw InvalidInput(invalid_value_message(entry(i, j), h_ij, "a finite value"));
  if (std::abs(h_ij - h_ji) > 1e-12 * scale) {
    std::ostringstream text;
    text.precision(17);
    text << entry(i, j) << " = " << h_ij << " differs from " << entry(j, i) << " = " << h_ji
         << "; allowed: a symmetric H = W^T M^-1 W";
    throw InvalidInput(text.str());
  }
}

void check_sizes(Index rows, Index cols, const Eigen::VectorXd& u_minus,
                 std::span<const ContactLaw> laws) {
  std::ostringstream text;
  if (rows != cols) {
    text << "H is " << rows << "x" << cols << "; allowed: a square matrix";
  } else if (u_minus.size() != rows) {
    text << "u_minus has " << u_minus.size() << " entries but H is " << rows << "x" << cols
         << "; allowed: one pre-impact velocity per contact";
  } else if (Index(laws.size()) != rows) {
    text << "laws has " << laws.size() << " entries but H is " << rows << "x" << cols
         << "; allowed: one contact law per contact";
  } else {
    return;
  }
  throw InvalidInput(text.str());
}

void check_velocities(const Eigen::VectorXd& u_minus) {
  for (Index j = 0; j < u_minus.size(); ++j)
    if (!std::isfinite(u_minus(j)))
      throw InvalidInput(invalid_value_message("u_minus(" + std::to_string(j) + ")", u_minus(j),
                                               "a finite velocity (m/s)"));
  if (u_minus.size() == 0 || u_minus.minCoeff() >= 0.0)
    throw InvalidInput(
        "no approaching contact: every u_minus(j) >= 0; allowed: at least one "
        "u_minus(j) < 0 (the convention is u < 0 approaching)");
}

Eigen::VectorXd checked_diagonal(const Eigen::VectorXd& diagonal) {
  for (Index j = 0; j < diagonal.size(); ++j)
    if (!(diagonal(j) > 0.0))
      throw InvalidInput(invalid_value_message(entry(j, j), diagonal(j),
                                               "H(j, j) > 0 (every contact must be able to "
                                               "move: H = W^T M^-1 W with W_j != 0)"));
  return diagonal;
}

void check_laws_and_samples(std::span<const ContactLaw> laws,
                            std::span<const Index> sampled_contacts) {
  const std::size_t m = laws.size();
  for (std::size_t j = 0; j < m; ++j) validate(laws[j], "contact " + std::to_string(j));
  for (Index c : sampled_contacts)
    if (c < 0 || c >= Index(m))
      throw InvalidInput(
          invalid_value_message("sampled_contacts entry", double(c),
                                "a contact index in [0, " + std::to_string(m) + ")"));
}

}  // namespace

Eigen::VectorXd checked_impact_input(const Eigen::SparseMatrix<double>& H,
                                     const Eigen::VectorXd& u_minus,
                                     std::span<const ContactLaw> laws,
                                     std::span<const Index> sampled_contacts) {
  check_sizes(H.rows(), H.cols(), u_minus, laws);
  const double scale = H.coeffs().size() ? H.coeffs().cwiseAbs().maxCoeff() : 0.0;
  for (Index j = 0; j < H.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(H, j); it; ++it)
      check_entry(it.row(), j, it.value(), H.coeff(j, it.row()), scale);
  check_velocities(u_minus);
  check_laws_and_samples(laws, sampled_contacts);
  return checked_diagonal(H.diagonal());
}

Eigen::VectorXd checked_impact_input(const Eigen::MatrixXd& H, const Eigen::VectorXd& u_minus,
                                     std::span<const ContactLaw> laws,
                                     std::span<const Index> sampled_contacts) {
  check_sizes(H.rows(), H.cols(), u_minus, laws);
  const double scale = H.size() ? H.cwiseAbs().maxCoeff() : 0.0;
  for (Index j = 0; j < H.cols(); ++j)
    for (Index i = 0; i < H.rows(); ++i) check_entry(i, j, H(i, j), H(j, i), scale);
  check_velocities(u_minus);
  check_laws_and_samples(laws, sampled_contacts);
  return checked_diagonal(H.diagonal());
}

}  // namespace mimpact::numerics
