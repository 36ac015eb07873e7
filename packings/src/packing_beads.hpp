#pragma once

// Where a packing's beads come from (packing_model.cpp builds the model from them): a lattice's
// sites, or a bead list's lines.

#include <Eigen/Dense>
#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <initializer_list>
#include <vector>

#include "mimpact/granular/cell_grid.hpp"
#include "mimpact/granular/run_limits.hpp"
#include "mimpact/packings/packing_scene.hpp"

namespace mimpact::packings {

// A bead or striker as the scene gives it.
struct Body {
  Vector centre;
  double radius;
  granular::Material material;
  Vector velocity = Vector::Zero(centre.size());
  Eigen::Vector3d spin = Eigen::Vector3d::Zero();  // rad/s; about z in the plane
  std::size_t line = 0;  // of a listed bead, in its file (for messages); 0: not listed
};

// the first `dimension` of these components
inline Vector vector_of(std::initializer_list<double> components, int dimension) {
  Vector v(dimension);
  std::copy_n(components.begin(), dimension, v.data());
  return v;
}
// a centre in three dimensions whatever the packing's (a planar packing's third coordinate is 0)
inline Eigen::Vector3d point_of(const Vector& centre) {
  Eigen::Vector3d at = Eigen::Vector3d::Zero();
  at.head(centre.size()) = centre;
  return at;
}
inline Vector vector_of(const std::vector<double>& components) {
  return Eigen::Map<const Eigen::VectorXd>(components.data(), Eigen::Index(components.size()));
}

// The memory a bead takes with its contacts (a bead touches 3 others on average in the plane, 6
// in space)
double bead_bytes(int dimension);

// The beads by their centres, for the contacts of a body of radius r: those within
// (1 + touching) of the sum of the radii. The beads are kept in classes of radii within a factor
// of 2, each in cells as wide as two of its largest touch, so that a bead's search visits the
// beads of its own size near it and not every small bead of a wide cell (a bead ringed by 20 000
// beads 3 000 times smaller found its contacts in 18 s with one class).
class TouchIndex {
 public:
  TouchIndex(const std::vector<Body>& beads, int dimension, double touching);
  // Calls visit(j) for every bead j whose centre may lie within touching reach of a body of
  // `radius` (m) at `centre`, by increasing j.
  template <class Visit>
  void visit(const Vector& centre, double radius, Visit&& visit) const {
    for (Eigen::Index j : candidates(centre, radius)) visit(j);
  }

 private:
  std::vector<Eigen::Index> candidates(const Vector& centre, double radius) const;

  struct RadiusClass {
    double largest_radius;  // m
    granular::CellGrid grid;
  };
  double touching_;
  std::vector<RadiusClass> classes_;
};

// the lattice's sites, row by row (and layer by layer)
std::vector<Body> lattice_beads(const LatticeSpec& lattice);

// "x,y,radius" (the plane) or "x,y,z,radius" (space), optionally with the velocity
// ",vx,vy" (",vx,vy,vz") and then the spin ",wz" (",wx,wy,wz"), then one bead per line. Messages
// name the line and column, never their content (a scene from elsewhere must not make mimpact show
// a file's lines).
std::vector<Body> listed_beads(const BeadListSpec& list, const std::filesystem::path& directory,
                               const granular::RunLimits& limits);

// The bead list's file: inside `directory` (the scene's, or --data-dir), a regular file. Its
// path is the scene's, so messages may name it; its content is never echoed.
std::filesystem::path bead_file(const BeadListSpec& list, const std::filesystem::path& directory);

}  // namespace mimpact::packings
