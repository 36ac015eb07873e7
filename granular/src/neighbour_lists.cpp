#include "mimpact/granular/neighbour_lists.hpp"

#include <algorithm>
#include <cmath>

namespace mimpact::granular {

NeighbourLists::NeighbourLists(const BeadGeometry& geometry, double skin)
    : geometry_(geometry),
      skin_(skin),
      cell_width_(2.0 * geometry.radius.maxCoeff() + skin),
      anchor_(geometry.position),
      grid_(cell_width_, geometry.dimension),
      near_(std::size_t(geometry.body_count())),
      walls_(std::size_t(geometry.body_count())) {
  for (Eigen::Index b = 0; b < geometry.body_count(); ++b)
    grid_.insert(std::int32_t(b), anchor_[std::size_t(b)]);
  // the criterion is symmetric: each body finds those that find it
  for (Eigen::Index b = 0; b < geometry.body_count(); ++b) link(b, false);
}

// b's list from the anchors of the bodies in the cells around its own; with `mutual`, b joins
// theirs
void NeighbourLists::link(Eigen::Index b, bool mutual) {
  const Eigen::Vector3d& x = anchor_[std::size_t(b)];
  const double rb = geometry_.radius(b);
  std::vector<std::int32_t>& mine = near_[std::size_t(b)];
  grid_.visit_near(x, cell_width_, [&](std::int32_t k) {
    if (k == b) return;
    const double reach = rb + geometry_.radius(k) + skin_;
    if ((anchor_[std::size_t(k)] - x).squaredNorm() >= reach * reach) return;
    mine.push_back(k);
    if (mutual) near_[std::size_t(k)].push_back(std::int32_t(b));
  });
  for (std::size_t w = 0; w < geometry_.walls.size(); ++w) {
    const Plane& wall = geometry_.walls[w];
    if (wall.normal.dot(x - wall.point) - rb < skin_) walls_[std::size_t(b)].push_back(int(w));
  }
}

void NeighbourLists::unlink(Eigen::Index b) {
  for (std::int32_t k : near_[std::size_t(b)]) std::erase(near_[std::size_t(k)], std::int32_t(b));
  near_[std::size_t(b)].clear();
  walls_[std::size_t(b)].clear();
  grid_.erase(std::int32_t(b));
}

void NeighbourLists::refresh(Eigen::Index b, const Eigen::Vector3d& position) {
  unlink(b);
  anchor_[std::size_t(b)] = position;
  grid_.insert(std::int32_t(b), position);
  link(b, true);
  ++refreshes_;
}

}  // namespace mimpact::granular
