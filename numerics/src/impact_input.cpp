#include "impact_input.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "mimpact/common/error.hpp"

namespace mimpact::numerics {

using Eigen::Index;

namespace {

std::string entry(Index i, Index j, const char* matrix = "H") {
  return std::string(matrix) + "(" + std::to_string(i) + ", " + std::to_string(j) + ")";
}

void check_entry(Index i, Index j, double h_ij, double h_ji, double scale,
                 const char* matrix = "H") {
  if (!std::isfinite(h_ij))
    throw InvalidInput(invalid_value_message(entry(i, j, matrix), h_ij, "a finite value"));
  if (std::abs(h_ij - h_ji) > 1e-12 * scale) {
    std::ostringstream text;
    text.precision(17);
    text << entry(i, j, matrix) << " = " << h_ij << " differs from " << entry(j, i, matrix) << " = "
         << h_ji << "; allowed: a symmetric " << matrix << " = W^T M^-1 W";
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
  // a law equal to the one before it is valid as that one is (a chain's laws are all one)
  for (std::size_t j = 0; j < m; ++j)
    if (j == 0 || !(laws[j] == laws[j - 1])) validate(laws[j], "contact " + std::to_string(j));
  for (Index c : sampled_contacts)
    if (c < 0 || c >= Index(m))
      throw InvalidInput(
          invalid_value_message("sampled_contacts entry", double(c),
                                "a contact index in [0, " + std::to_string(m) + ")"));
}

// The tangential rows' offsets: first_row[0] = 0, then 0, 1 or 2 rows per contact.
void check_row_offsets(const TangentialRows& rows, Index m) {
  const auto& first = rows.first_row;
  if (Index(first.size()) != m + 1 || first.front() != 0)
    throw InvalidInput("tangential rows' first_row has " + std::to_string(first.size()) +
                       " entries; allowed: one per contact plus one (" + std::to_string(m + 1) +
                       "), the first 0");
  for (Index j = 0; j < m; ++j)
    if (const int count = rows.rows_of(j); count < 0 || count > 2)
      throw InvalidInput(invalid_value_message(
          "contact " + std::to_string(j) + "'s tangential rows", double(count),
          "0 (frictionless), 1 (a tangent in the plane) or 2 (a tangent plane in space)"));
}

void check_tangential_blocks(const TangentialRows& rows, Index m) {
  const Index r = rows.rows();
  std::ostringstream text;
  if (rows.normal_to_tangent.rows() != r || rows.normal_to_tangent.cols() != m)
    text << "H_tn is " << rows.normal_to_tangent.rows() << "x" << rows.normal_to_tangent.cols();
  else if (rows.tangent.rows() != r || rows.tangent.cols() != r)
    text << "H_tt is " << rows.tangent.rows() << "x" << rows.tangent.cols();
  else if (rows.slip_minus.size() != r)
    text << "slip_minus has " << rows.slip_minus.size() << " entries";
  if (!text.str().empty()) {
    text << "; allowed: " << r << " tangential rows and " << m << " contacts (H_tn rows x "
         << "contacts, H_tt rows x rows, one slip per row)";
    throw InvalidInput(text.str());
  }
  for (Index k = 0; k < rows.normal_to_tangent.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(rows.normal_to_tangent, k); it; ++it)
      if (!std::isfinite(it.value()))
        throw InvalidInput(
            invalid_value_message(entry(it.row(), k, "H_tn"), it.value(), "a finite value"));
  const Eigen::SparseMatrix<double>& tt = rows.tangent;
  const double scale = tt.nonZeros() ? tt.coeffs().cwiseAbs().maxCoeff() : 0.0;
  for (Index k = 0; k < tt.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(tt, k); it; ++it)
      check_entry(it.row(), k, it.value(), tt.coeff(k, it.row()), scale, "H_tt");
  for (Index row = 0; row < r; ++row) {
    if (!std::isfinite(rows.slip_minus(row)))
      throw InvalidInput(invalid_value_message("slip_minus(" + std::to_string(row) + ")",
                                               rows.slip_minus(row), "a finite velocity (m/s)"));
    if (!(tt.coeff(row, row) > 0.0))
      throw InvalidInput(invalid_value_message(entry(row, row, "H_tt"), tt.coeff(row, row),
                                               "H_tt(r, r) > 0 (every tangent must be able to "
                                               "move: W_t != 0)"));
  }
}

}  // namespace

void checked_friction(std::span<const ContactLaw> laws, const TangentialRows* rows,
                      bool integrates_friction, std::string_view integrator) {
  const Index m = Index(laws.size());
  if (rows) {
    check_row_offsets(*rows, m);
    check_tangential_blocks(*rows, m);
  }
  for (Index j = 0; j < m; ++j) {
    if (const double ratio = laws[std::size_t(j)].tangential_stiffness_ratio; ratio != 0.0)
      throw InvalidInput(invalid_value_message(
          "contact " + std::to_string(j) + "'s tangential_stiffness_ratio", ratio,
          "0 in the LZB impact, whose tangential response is rigid (Coulomb's law alone); the "
          "compliant integrator takes a Mindlin spring"));
    const double mu = laws[std::size_t(j)].friction;
    if (mu == 0.0) continue;
    const std::string field = "contact " + std::to_string(j) + "'s friction";
    if (!(std::isfinite(mu) && mu > 0.0))
      throw InvalidInput(invalid_value_message(field, mu, "a finite mu >= 0"));
    if (!rows || rows->rows_of(j) == 0)
      throw InvalidInput(invalid_value_message(
          field, mu, "0 for a contact without tangential rows (give its rows in TangentialRows)"));
    if (!integrates_friction)
      throw InvalidInput(
          invalid_value_message(field, mu,
                                "0 with the " + std::string(integrator) +
                                    " integrator, which does not integrate friction; the adaptive "
                                    "and impulse-step ones do"));
  }
}

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
