#pragma once

// Steel beads of 5 mm (C1's steel, docs/experiments.md) for the moving geometry's tests.

#include <vector>

#include "mimpact/granular/bead_geometry.hpp"

namespace mimpact::granular {

inline const Material kSteel{.density = 7780.0, .young = 203e9, .poisson = 0.3};
constexpr double kRadius = 0.005;

// Equal steel beads at `positions`, Hertz's law with restitution e and no walls.
inline BeadGeometry steel_beads(const std::vector<Eigen::Vector3d>& positions, int dimension = 2,
                                double restitution = 1.0) {
  BeadGeometry g;
  g.dimension = dimension;
  g.position = positions;
  const Eigen::Index n = Eigen::Index(positions.size());
  g.radius = Eigen::VectorXd::Constant(n, kRadius);
  g.mass = Eigen::VectorXd::Constant(n, bead_mass(kRadius, kSteel));
  g.material.assign(std::size_t(n), kSteel);
  g.shape.exponent = 1.5;
  g.shape.restitution = restitution;
  return g;
}

}  // namespace mimpact::granular
