#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace mimpact::granular {

// The one neighbour search of the granular layer: a uniform grid of cells `width` wide (m)
// holding bodies by a point of each, hashed so that only occupied cells are stored (bodies
// flying off a packing cost nothing). The bodies within a distance r of a point are among those
// of the cells within ceil(r / width) of its own, along the first `dimension` axes. It finds a
// packing's contacts when it is built (packings/) and keeps the moving geometry's Verlet lists
// (NeighbourLists).
class CellGrid {
 public:
  CellGrid(double width, int dimension) : width_(width), dimension_(dimension) {}

  void insert(std::int32_t body, const Eigen::Vector3d& x) {
    if (std::size_t(body) >= cell_.size()) cell_.resize(std::size_t(body) + 1);
    cell_[std::size_t(body)] = cell_of(x);
    cells_[cell_[std::size_t(body)]].push_back(body);
  }
  // Takes body out of the cell it was inserted in.
  void erase(std::int32_t body) { std::erase(cells_[cell_[std::size_t(body)]], body); }

  // Calls visit(k) for every body k of the cells within `reach` (m) of x's: a superset of those
  // whose point lies within reach of x, in a fixed order (the cells by axis, then by insertion).
  // A reach of more rings of cells around x's than there are occupied cells (a striker far
  // larger than the beads) visits every occupied cell instead, in the grid's own order.
  template <class Visit>
  void visit_near(const Eigen::Vector3d& x, double reach, Visit&& visit) const {
    const double ring_count = std::ceil(reach / width_);
    if (!(ring_count <= 1.0) &&
        !(std::pow(2.0 * ring_count + 1.0, dimension_) <= double(cells_.size()))) {
      for (const auto& [cell, bodies] : cells_)
        for (std::int32_t k : bodies) visit(k);
      return;
    }
    const Cell c = cell_of(x);
    const auto rings = std::int64_t(std::max(ring_count, 0.0));
    const std::int64_t ry = dimension_ >= 2 ? rings : 0, rz = dimension_ == 3 ? rings : 0;
    for (std::int64_t dx = -rings; dx <= rings; ++dx)
      for (std::int64_t dy = -ry; dy <= ry; ++dy)
        for (std::int64_t dz = -rz; dz <= rz; ++dz) {
          const auto found = cells_.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (found == cells_.end()) continue;
          for (std::int32_t k : found->second) visit(k);
        }
  }

 private:
  using Cell = std::array<std::int64_t, 3>;
  struct CellHash {
    std::size_t operator()(const Cell& c) const {
      return std::size_t(c[0] * 73856093) ^ std::size_t(c[1] * 19349663) ^
             std::size_t(c[2] * 83492791);
    }
  };
  Cell cell_of(const Eigen::Vector3d& x) const {
    Cell c;
    // (a cell index beyond +-2^62 is held there: those far cells are one key, still a superset)
    constexpr double kFarthest = 0x1p62;
    for (int k = 0; k < 3; ++k)
      c[std::size_t(k)] =
          std::int64_t(std::clamp(std::floor(x(k) / width_), -kFarthest, kFarthest));
    return c;
  }

  double width_;
  int dimension_;
  std::vector<Cell> cell_;  // per body, the cell it was inserted in
  std::unordered_map<Cell, std::vector<std::int32_t>, CellHash> cells_;
};

}  // namespace mimpact::granular
