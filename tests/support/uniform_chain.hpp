#pragma once

// The Delassus operator of n+1 equal masses on a line (n contacts), built by hand for the
// numerics tests: H = tridiag(-1/m, 2/m, -1/m).

#include <Eigen/SparseCore>
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

}  // namespace mimpact::testing
