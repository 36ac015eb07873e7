// The granular layer's one neighbour search (CellGrid): the candidates it hands for a point hold
// every body within the reach asked, against a brute-force search over random bodies in one, two
// and three dimensions, for reaches below, at and above the cells' width; and a body erased or
// moved is found only where it is now.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "mimpact/granular/cell_grid.hpp"

namespace mimpact::granular {
namespace {

TEST(CellGrid, FindsEveryBodyWithinTheReachAsBruteForceDoes) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  for (int dimension : {1, 2, 3}) {
    const double width = 0.1;
    std::vector<Eigen::Vector3d> points(400, Eigen::Vector3d::Zero());
    CellGrid grid(width, dimension);
    for (std::size_t i = 0; i < points.size(); ++i) {
      for (int k = 0; k < dimension; ++k) points[i](k) = coordinate(random);
      grid.insert(std::int32_t(i), points[i]);
    }
    for (double reach : {0.05, 0.1, 0.25}) {
      std::size_t found_within = 0;
      for (const Eigen::Vector3d& x : points) {
        std::vector<std::int32_t> candidates;
        grid.visit_near(x, reach, [&](std::int32_t k) { candidates.push_back(k); });
        std::sort(candidates.begin(), candidates.end());
        for (std::size_t k = 0; k < points.size(); ++k)
          if ((points[k] - x).norm() <= reach) {
            EXPECT_TRUE(std::binary_search(candidates.begin(), candidates.end(), std::int32_t(k)))
                << "dimension " << dimension << ", reach " << reach;
            ++found_within;
          }
        // the candidates are the cells around x: at most (2 ceil(reach / width) + 1)^d cells
        EXPECT_LT(candidates.size(), points.size());
      }
      EXPECT_GT(found_within, points.size());  // the search had neighbours to find
    }
  }
}

// A reach of far more cells than the grid holds (a striker 1e12 times a bead's size, or an
// infinite reach) hands every body at once, without counting the empty cells around.
TEST(CellGrid, AReachBeyondTheOccupiedCellsHandsEveryBody) {
  CellGrid grid(1e-3, 3);
  for (std::int32_t k = 0; k < 50; ++k) grid.insert(k, Eigen::Vector3d(1e-3 * k, 0.0, 0.0));
  for (double reach : {1e9, 1e300, double(INFINITY)}) {
    std::vector<std::int32_t> found;
    grid.visit_near(Eigen::Vector3d::Zero(), reach, [&](std::int32_t k) { found.push_back(k); });
    std::sort(found.begin(), found.end());
    ASSERT_EQ(found.size(), 50u) << reach;
    for (std::int32_t k = 0; k < 50; ++k) EXPECT_EQ(found[std::size_t(k)], k);
  }
}

TEST(CellGrid, ABodyMovedIsFoundWhereItIsNow) {
  CellGrid grid(1.0, 2);
  grid.insert(0, Eigen::Vector3d(0.5, 0.5, 0.0));
  grid.insert(1, Eigen::Vector3d(0.6, 0.5, 0.0));
  grid.erase(0);
  grid.insert(0, Eigen::Vector3d(10.5, 0.5, 0.0));
  std::vector<std::int32_t> near_origin, far;
  grid.visit_near(Eigen::Vector3d(0.5, 0.5, 0.0), 1.0,
                  [&](std::int32_t k) { near_origin.push_back(k); });
  grid.visit_near(Eigen::Vector3d(10.5, 0.5, 0.0), 1.0, [&](std::int32_t k) { far.push_back(k); });
  EXPECT_EQ(near_origin, std::vector<std::int32_t>{1});
  EXPECT_EQ(far, std::vector<std::int32_t>{0});
}

}  // namespace
}  // namespace mimpact::granular
