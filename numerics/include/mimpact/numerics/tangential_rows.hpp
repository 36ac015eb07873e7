#pragma once

#include <Eigen/SparseCore>
#include <vector>

// The tangential rows of an impact with Coulomb friction (docs/model.md, "Friction"): beside the
// normal rows' Delassus operator H = W_n^T M^-1 W_n, the blocks of the full operator that the
// tangent directions add, and where each contact's rows are.
namespace mimpact::numerics {

// Contact j has rows first_row[j] .. first_row[j + 1] - 1: none (frictionless), one (a tangent
// in the plane) or two (a tangent plane in space). With the impulses P_n (one per contact) and
// P_t (one per row), the relative velocities are
//   u = u- + H P_n + H_tn^T P_t     (normal, one per contact)
//   s = s- + H_tn P_n + H_tt P_t    (tangential: the contact points' slip, one per row)
// and the full operator [H H_tn^T; H_tn H_tt] = W^T M^-1 W is symmetric positive semi-definite.
// Contact j's Coulomb coefficient is its law's `friction`.
struct TangentialRows {
  Eigen::SparseMatrix<double> normal_to_tangent;  // H_tn: rows x contacts (1/kg)
  Eigen::SparseMatrix<double> tangent;            // H_tt: rows x rows, symmetric (1/kg)
  Eigen::VectorXd slip_minus;                     // s-: pre-impact slip, one per row (m/s)
  std::vector<Eigen::Index> first_row;            // contacts + 1 offsets, first_row[0] = 0

  Eigen::Index rows() const { return first_row.empty() ? 0 : first_row.back(); }
  int rows_of(Eigen::Index contact) const {
    return int(first_row[std::size_t(contact) + 1] - first_row[std::size_t(contact)]);
  }
};

}  // namespace mimpact::numerics
