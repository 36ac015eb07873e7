#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <cstdint>
#include <span>
#include <vector>

#include "mimpact/numerics/contact_law.hpp"
#include "mimpact/numerics/tangential_rows.hpp"

// Bodies that turn and contacts that rub (docs/model.md, section 16): the solid spheres of a
// granular scene with their angular velocities, and the tangent rows of its frictional contacts
// in the frozen configuration of the impact.
namespace mimpact::granular {

// A contact as the tangent rows see it: its two bodies (second -1: a wall) and its unit normal,
// from the first body to the second (a wall's: towards its bead, the first body).
struct RubbingContact {
  Eigen::Index first = 0;
  Eigen::Index second = -1;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();
};

// Solid spheres that turn, present in a scene's model when a contact has friction or a body
// spins; absent, the bodies only translate and nothing here costs anything.
//
// Each frictional contact has tangent rows (one in the plane, two in space; tangent_frame).
// Row r's slip is the relative velocity of the contact points along its tangent t,
//   s_r = W_t(:, r)^T v + R_t(:, r)^T omega,
// a body whose normal gradient is sigma n (sigma = +1 for the second body or a wall's bead,
// -1 for the first) touching at its centre - sigma radius n: its translations' gradient is
// sigma t and its rotation's -radius (n x t) (Stronge, "Impact Mechanics", 2000, chapter 5).
struct Rotation {
  int components = 0;                // of an angular velocity: 1 in the plane (about z), 3 in space
  Eigen::VectorXd inertia;           // kg m^2, per body: a solid sphere's 2/5 m r^2
  Eigen::VectorXd angular_velocity;  // rad/s before the impact, `components` per body
  Eigen::SparseMatrix<double> W_t;   // translation coordinates x tangent rows
  Eigen::SparseMatrix<double> R_t;   // angular components x tangent rows
  numerics::TangentialRows tangential;  // H_tn, H_tt, s-, each contact's rows

  Eigen::Index body_count() const { return inertia.size(); }
  // body b's angular velocity among `values` (components per body)
  auto of(const Eigen::VectorXd& values, Eigen::Index body) const {
    return values.segment(components * body, components);
  }
};

// The angular velocities (rad/s, components per body) of bodies turning at `before` once the
// tangential impulses `tangential` (N s, per row) act: before + I^-1 R_t P_t.
Eigen::VectorXd turned(const Rotation& rotation, const Eigen::VectorXd& before,
                       const Eigen::VectorXd& tangential);

// The unit tangents of a contact whose unit normal is n: in the plane t = n turned by +90
// degrees about z (so n x t = z); in space t1 along z x n (x x n when n is along z) and
// t2 = n x t1. Returns their count, 1 or 2.
int tangent_frame(const Eigen::Vector3d& n, int dimension, Eigen::Vector3d (&tangents)[2]);

// What the tangent rows are built from: the bodies (`dimension` translations each, masses per
// coordinate, velocities), their radii, inertias and angular velocities, and the contacts with
// their laws (rows for those whose friction > 0).
struct RotationInput {
  int dimension = 2;
  const Eigen::VectorXd& mass;              // kg, per translation coordinate
  const Eigen::VectorXd& velocity;          // m/s, per translation coordinate
  const Eigen::SparseMatrix<double>& W;     // translation coordinates x contacts (normal rows)
  const Eigen::VectorXd& radius;            // m, per body
  const Eigen::VectorXd& angular_velocity;  // rad/s, components per body
  std::span<const RubbingContact> contacts;
  std::span<const numerics::ContactLaw> laws;
};

// The bodies as turning solid spheres with their frictional contacts' rows, H_tn = W_t^T M^-1 W,
// H_tt = W_t^T M^-1 W_t + R_t^T I^-1 R_t and s- = W_t^T v + R_t^T omega.
Rotation build_rotation(const RotationInput& input);

// Rotational kinetic energy (J) of bodies turning at `angular_velocity`.
double rotational_energy(const Rotation& rotation, const Eigen::VectorXd& angular_velocity);

}  // namespace mimpact::granular
