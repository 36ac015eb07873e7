#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "mimpact/granular/bead_geometry.hpp"
#include "mimpact/granular/cell_grid.hpp"

namespace mimpact::granular {

// Verlet lists that follow the beads: each body keeps an anchor (where it was when its list was
// last made) and the bodies and walls within `skin` of it there. While every body stays within
// skin / 2 of its anchor, two bodies that are in no list of each other cannot touch; a body
// that may leave that ball refreshes its own list alone (the others keep theirs), through a
// CellGrid of cells as wide as the widest reach. The work of a refresh is the neighbours of one
// body, so the search costs what moves: a body at rest never refreshes.
class NeighbourLists {
 public:
  NeighbourLists(const BeadGeometry& geometry, double skin);

  double skin() const { return skin_; }
  // bodies, and walls, that body b may touch while it and they stay near their anchors
  const std::vector<std::int32_t>& bodies_near(Eigen::Index b) const {
    return near_[std::size_t(b)];
  }
  const std::vector<std::int32_t>& walls_near(Eigen::Index b) const {
    return walls_[std::size_t(b)];
  }
  const Eigen::Vector3d& anchor(Eigen::Index b) const { return anchor_[std::size_t(b)]; }
  // body b's list made again around `position`
  void refresh(Eigen::Index b, const Eigen::Vector3d& position);
  std::int64_t refreshes() const { return refreshes_; }

 private:
  void unlink(Eigen::Index b);
  void link(Eigen::Index b, bool mutual);

  const BeadGeometry& geometry_;
  double skin_, cell_width_;
  std::vector<Eigen::Vector3d> anchor_;
  CellGrid grid_;  // of the anchors
  std::vector<std::vector<std::int32_t>> near_, walls_;
  std::int64_t refreshes_ = 0;
};

}  // namespace mimpact::granular
