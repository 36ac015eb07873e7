#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mimpact/granular/bead_geometry.hpp"
#include "mimpact/granular/rotation.hpp"
#include "mimpact/numerics/contact_law.hpp"

namespace mimpact::granular {

// What the impact runs read of a granular scene, in generalized coordinates: one per bead on a
// line (chains::ChainModel), `dimension` per bead in a packing (packings::PackingModel, two in
// the plane). Coordinate
// `dimension * b + k` is component k of body b's position, and body b is the kernel system b of
// the scene's NonSmoothDynamicalSystem.
struct ContactModel {
  int dimension = 1;              // coordinates per body
  Eigen::VectorXd mass;           // kg, per coordinate (a body's mass on each of its own)
  Eigen::VectorXd velocity;       // pre-impact velocity (m/s), per coordinate
  Eigen::SparseMatrix<double> W;  // coordinates x contacts, column j = grad g_j
  Eigen::SparseMatrix<double> H;  // W^T M^-1 W
  Eigen::VectorXd u_minus;        // W^T v, pre-impact relative velocities (m/s)
  std::vector<numerics::ContactLaw> laws;
  // when each striker touches its target (s): gap / speed, one per striker
  std::vector<double> striker_arrivals;
  // N: a constant force presses the bodies together; they start at their static overlaps
  double precompression = 0.0;
  double largest_static_overlap = 0.0;  // m: the compliant contacts start this far in
  // the bodies as spheres, for the compliant contacts in the moving geometry (a packing); none
  // for a chain, whose gaps are exactly linear
  std::shared_ptr<const BeadGeometry> beads;
  // the bodies turn (a contact rubs or a body spins): then the kernel's body b has `dimension`
  // translations and rotation->components angular coordinates, in this order
  std::optional<Rotation> rotation;

  Eigen::Index body_count() const { return mass.size() / dimension; }
  Eigen::Index contact_count() const { return Eigen::Index(laws.size()); }
};

// Kinetic energy (J) of the bodies moving with `velocity` (per coordinate).
double kinetic_energy(const ContactModel& model, const Eigen::VectorXd& velocity);

// The kernel's generalized velocity of the model's bodies (body by body: translations, then
// with rotation the angular velocity) as `velocity` (per translation coordinate) and
// `angular_velocity` (components per body; empty without rotation).
void split_velocities(const ContactModel& model, const Eigen::VectorXd& generalized,
                      Eigen::VectorXd& velocity, Eigen::VectorXd& angular_velocity);

// The largest compression (m) of contact j alone, struck at its approach speed u_j-:
// ((1 + eta) m u^2 / (2 K))^(1 / (1 + eta)), m = 1 / H_jj.
double lone_overlap(const ContactModel& model, Eigen::Index j);
// The overlap (m) that sets the contacts' scale: lone_overlap, the smallest over the
// approaching contacts; infinite when no contact approaches.
double impact_overlap(const ContactModel& model);

// The impulse that sets the impact's scale (N s): the smallest momentum m |v| of a moving
// body, i.e. of a striker. delta_p is best chosen as a share of it.
double smallest_momentum(const ContactModel& model);
// The largest momentum m |v| of a moving body (N s): the impact takes at least this over
// delta_p steps to take it up.
double largest_momentum(const ContactModel& model);
// The natural impulse of the approaching contacts, max_j |u_j-| / H_jj (N s): what
// relative_delta_p is a share of (numerics::natural_impulse).
double natural_impulse(const ContactModel& model);

// Throws InvalidInput when an approaching contact's natural energy, m u^2 / 2 with m = 1 / H_jj,
// leaves [1e-250, 1e250] J: the integrators' tolerances are this energy times factors down to
// 1e-44, which must stay normal doubles (a packing of beads of density 1e-300 never ended).
void check_impact_scales(const ContactModel& model);

// Throws InvalidInput naming `field` unless the principal impulse step delta_p (N s) can
// resolve the impact: finite, below the smallest momentum m V (a coarser step resolves no
// approach, so the strikers would pass through their targets), and not so fine that the
// impact needs more than max_steps steps (it takes at least the largest momentum over
// delta_p).
void check_delta_p(const ContactModel& model, double delta_p, std::int64_t max_steps,
                   const std::string& field);

}  // namespace mimpact::granular
