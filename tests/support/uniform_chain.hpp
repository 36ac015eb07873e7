#pragma once

// The Delassus operator of n+1 equal masses on a line (n contacts), built by hand for the
// numerics tests: H = tridiag(-1/m, 2/m, -1/m).

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <cmath>
#include <numbers>
#include <vector>

namespace mimpact::testing {

inline Eigen::SparseMatrix<double> uniform_chain_delassus(int contacts, double mass) {
  std::vector<Eigen::Triplet<double>> entries;
  for (int j = 0; j < contacts; ++j) {
    entries.emplace_back(j, j, 2.0 / mass);
    if (j + 1 < contacts) {
      entries.emplace_back(j, j + 1, -1.0 / mass);
      entries.emplace_back(j + 1, j, -1.0 / mass);
    }
  }
  Eigen::SparseMatrix<double> H(contacts, contacts);
  H.setFromTriplets(entries.begin(), entries.end());
  return H;
}

// Chain C1 of Nguyen & Brogliato (2011): 21 steel beads of radius 10 mm touching in a row, the
// first at 1 m/s (or `beads` of them).
struct UniformChain {
  int beads = 21;
  double mass = 4.0 / 3.0 * std::numbers::pi * 1e-6 * 7780.0;  // kg
  // Hertz between equal spheres of radius R: K = 4/3 E* sqrt(R / 2) (N/m^1.5)
  double stiffness = 4.0 / 3.0 * (203e9 / (2.0 * (1.0 - 0.09))) * std::sqrt(0.005);

  int contacts() const { return beads - 1; }
  Eigen::SparseMatrix<double> delassus() const { return uniform_chain_delassus(contacts(), mass); }
  // the first bead approaches the second at 1 m/s, the others rest
  Eigen::VectorXd struck() const {
    Eigen::VectorXd u_minus = Eigen::VectorXd::Zero(contacts());
    u_minus(0) = -1.0;
    return u_minus;
  }
  // the beads' velocities after the impulses: contact j pushes bead j back and bead j + 1 on
  Eigen::VectorXd velocity_after(const Eigen::VectorXd& impulse) const {
    Eigen::VectorXd v = Eigen::VectorXd::Zero(beads);
    v(0) = 1.0;
    for (int j = 0; j < contacts(); ++j) {
      v(j) -= impulse(j) / mass;
      v(j + 1) += impulse(j) / mass;
    }
    return v;
  }
};

}  // namespace mimpact::testing
