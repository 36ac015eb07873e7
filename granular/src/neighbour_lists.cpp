#include "mimpact/granular/neighbour_lists.hpp"

#include <algorithm>
#include <cmath>

namespace mimpact::granular {

NeighbourLists::NeighbourLists(const BeadGeometry& geometry, double skin)
    : geometry_(geometry),
      skin_(skin),
      cell_width_(2.0 * geometry.radius.maxCoeff() + skin),
      anchor_(geometry.position),
      cell_(std::size_t(geometry.body_count())),
      near_(std::size_t(geometry.body_count())),
      walls_(std::size_t(geometry.body_count())) {
  for (Eigen::Index b = 0; b < geometry.body_count(); ++b) {
    cell_[std::size_t(b)] = cell_of(anchor_[std::size_t(b)]);
    grid_[cell_[std::size_t(b)]].push_back(std::int32_t(b));
  }
  // the criterion is symmetric: each body finds those that find it
  for (Eigen::Index b = 0; b < geometry.body_count(); ++b) link(b, false);
}

NeighbourLists::Cell NeighbourLists::cell_of(const Eigen::Vector3d& x) const {
  Cell c;
  for (int k = 0; k < 3; ++k) c[std::size_t(k)] = std::int64_t(std::floor(x(k) / cell_width_));
  return c;
}

// b's list from the anchors of the bodies in the cells around its own; with `mutual`, b joins
// theirs
void NeighbourLists::link(Eigen::Index b, bool mutual) {
  const Eigen::Vector3d& x = anchor_[std::size_t(b)];
  const double rb = geometry_.radius(b);
  const Cell& c = cell_[std::size_t(b)];
  const int reach_z = geometry_.dimension == 3 ? 1 : 0;
  const int reach_y = geometry_.dimension >= 2 ? 1 : 0;
  std::vector<std::int32_t>& mine = near_[std::size_t(b)];
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -reach_y; dy <= reach_y; ++dy)
      for (int dz = -reach_z; dz <= reach_z; ++dz) {
        const auto found = grid_.find({c[0] + dx, c[1] + dy, c[2] + dz});
        if (found == grid_.end()) continue;
        for (std::int32_t k : found->second) {
          if (k == b) continue;
          const double reach = rb + geometry_.radius(k) + skin_;
          if ((anchor_[std::size_t(k)] - x).squaredNorm() >= reach * reach) continue;
          mine.push_back(k);
          if (mutual) near_[std::size_t(k)].push_back(std::int32_t(b));
        }
      }
  for (std::size_t w = 0; w < geometry_.walls.size(); ++w) {
    const Plane& wall = geometry_.walls[w];
    if (wall.normal.dot(x - wall.point) - rb < skin_) walls_[std::size_t(b)].push_back(int(w));
  }
}

void NeighbourLists::unlink(Eigen::Index b) {
  for (std::int32_t k : near_[std::size_t(b)]) std::erase(near_[std::size_t(k)], std::int32_t(b));
  near_[std::size_t(b)].clear();
  walls_[std::size_t(b)].clear();
  std::erase(grid_[cell_[std::size_t(b)]], std::int32_t(b));
}

void NeighbourLists::refresh(Eigen::Index b, const Eigen::Vector3d& position) {
  unlink(b);
  anchor_[std::size_t(b)] = position;
  cell_[std::size_t(b)] = cell_of(position);
  grid_[cell_[std::size_t(b)]].push_back(std::int32_t(b));
  link(b, true);
  ++refreshes_;
}

}  // namespace mimpact::granular
