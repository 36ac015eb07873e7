#pragma once

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "mimpact/granular/contact_model.hpp"
#include "mimpact/granular/run_limits.hpp"
#include "mimpact/kernel/non_smooth_dynamical_system.hpp"
#include "mimpact/packings/packing_scene.hpp"

namespace mimpact::packings {

// Beads closer than this share of the sum of their radii touch (a contact, at the distance of
// their centres); closer still, they overlap, which the scene may not hold. Lattices come out
// to 1e-15; a bead list written with 10 significant digits still touches.
constexpr double kTouching = 1e-9;

// One contact of the packing: two bodies, or a body and a wall. The normal is frozen at the
// configuration of the impact (the LZB model's: the impact takes no time, so the bodies do not
// move; docs/model.md, section 13): g = n . (q_second - q_first) - rest for two bodies,
// g = n . q_first - rest for a wall, with n the wall's normal.
struct PackingContact {
  Eigen::Index first = 0;
  Eigen::Index second = -1;  // -1: a wall
  int wall = -1;             // the wall's index in the scene, or -1
  Vector normal;             // unit, from first to second (or the wall's, towards the beads)
  double rest = 0.0;         // m: g = 0 at the configuration the contact closes in
};

// A packing of beads: one translation per dimension and bead, rigid walls, strikers flying at
// beads of the packing. Bodies are the beads (a lattice row by row), then the strikers;
// coordinate d b + k is component k of body b (d = dimension: 2 for the planar packings of the
// scenes). When a contact rubs or a body spins, the beads turn too (ContactModel::rotation).
// One code path for any dimension.
struct PackingModel : granular::ContactModel {
  PackingModel() { dimension = 2; }

  Eigen::Index bead_count = 0;  // of the packing, strikers apart
  Eigen::VectorXd radius;       // m, per body
  Eigen::MatrixXd position;     // m, of the centres at t = 0: a row per body
  std::vector<PackingContact> contacts;
  std::vector<Vector> wall_points, wall_normals;  // m; unit, towards the beads
  int layers = 0, rows = 0, columns = 0;  // of a lattice (0 for a bead list; layers 0 in the plane)

  // body b's components of `values` (per coordinate: velocities, impulses)
  Vector of(const Eigen::VectorXd& values, Eigen::Index body) const {
    return values.segment(dimension * body, dimension);
  }
};

// Places the beads, walls and strikers, finds the closed contacts by a neighbour search
// (Boost.Geometry's R-tree) and assembles W, H and u-. Throws InvalidInput naming the bodies for
// beads that overlap, a bead in a wall, an empty bead list, a striker whose place overlaps a
// bead or a wall, and a packing struck by no approaching striker; and before building, for a
// packing that needs more memory than `limits` allow.
PackingModel build_packing_model(const PackingScene& scene, const granular::RunLimits& limits = {});

// The packing in the kernel's terms: one LagrangianLinearTIDS of `dimension` coordinates per body,
// one interaction per contact with a LinearRelation (the frozen normal) and an LzbLaw.
std::shared_ptr<kernel::NonSmoothDynamicalSystem> build_packing_system(const PackingModel& model);

// Total momentum (N s) of the bodies moving with `velocity` (per coordinate).
Vector momentum(const PackingModel& model, const Eigen::VectorXd& velocity);

// Total angular momentum (N m s) about the origin, sum of m x x v + I omega, of the bodies moving
// with `velocity` and turning at `angular_velocity` (empty: not turning) where they are at
// `time` (s), each flown from its start at its velocity before the impact, or at `position` (m,
// per coordinate) where given: [Lz] in the plane, [Lx, Ly, Lz] in space.
Vector angular_momentum(const PackingModel& model, const Eigen::VectorXd& velocity,
                        const Eigen::VectorXd& angular_velocity, double time,
                        const Eigen::VectorXd& position = Eigen::VectorXd());

// The body of bead (row, column) of a planar lattice, (layer, row, column) of a three-dimensional
// one, or bead `index` of a bead list.
Eigen::Index body_of_target(const PackingModel& model, const std::vector<int>& target);

}  // namespace mimpact::packings
