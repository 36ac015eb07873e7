#include "mimpact/numerics/delassus.hpp"

#include <gtest/gtest.h>

#include "mimpact/common/error.hpp"

namespace mimpact::numerics {
namespace {

TEST(Delassus, ChainOfThreeBodiesIsTridiagonal) {
  // contact i between bodies i and i+1: W has -1 at (i, i) and +1 at (i+1, i)
  Eigen::SparseMatrix<double> W(3, 2);
  W.insert(0, 0) = -1.0;
  W.insert(1, 0) = 1.0;
  W.insert(1, 1) = -1.0;
  W.insert(2, 1) = 1.0;
  const Eigen::Vector3d inverse_mass(1.0, 0.5, 0.25);
  const Eigen::MatrixXd H = assemble_delassus(W, inverse_mass);
  Eigen::Matrix2d expected;
  expected << 1.5, -0.5, -0.5, 0.75;
  EXPECT_TRUE(H.isApprox(expected, 1e-15)) << H;
}

TEST(Delassus, WrongSizeOrNegativeInverseMassIsAnError) {
  Eigen::SparseMatrix<double> W(3, 2);
  EXPECT_THROW(assemble_delassus(W, Eigen::Vector2d(1, 1)), InvalidInput);
  EXPECT_THROW(assemble_delassus(W, Eigen::Vector3d(1, -1, 1)), InvalidInput);
}

}  // namespace
}  // namespace mimpact::numerics
