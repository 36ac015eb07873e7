#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mimpact/granular/bead_geometry.hpp"
#include "mimpact/granular/rotation.hpp"
#include "mimpact/kernel/simulation.hpp"
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
  // m: bodies this close to touching are in contact, a share of the largest sum of radii (the
  // scene's lengths: a packing of beads of radius 1e6 m has gaps of 1e-9 m by rounding)
  double touching_tolerance = 1e-9;
  // the bodies as spheres, for the compliant contacts in the moving geometry (a packing); none
  // for a chain, whose gaps are exactly linear
  std::shared_ptr<const BeadGeometry> beads;
  // the bodies turn (a contact rubs or a body spins): then the kernel's body b has `dimension`
  // translations and rotation->components angular coordinates, in this order
  std::optional<Rotation> rotation;

  Eigen::Index body_count() const { return mass.size() / dimension; }
  Eigen::Index contact_count() const { return Eigen::Index(laws.size()); }
};

// The kernel simulation's options for the model: gaps down to twice its touching tolerance and
// its static overlaps are contacts at the start.
kernel::SimulationOptions simulation_options(const ContactModel& model);

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
// The message names the contact's bodies by contact_name(j), the scene's names.
void check_impact_scales(const ContactModel& model,
                         const std::function<std::string(Eigen::Index)>& contact_name);

// Throws InvalidInput unless overlaps of `overlap` (m) span 1e3 rounding errors (three
// significant digits) of coordinates up to `largest_coordinate` (m): gaps are differences of
// coordinates, and a contact pressed less than their rounding runs on round-off (a chain struck
// at 1e-20 m/s stored 1e-33 J at rest). `advice` ends the message: what the scene can change.
void check_overlap_resolved(double overlap, double largest_coordinate, const std::string& advice);
// check_overlap_resolved's advice to a scene: faster strikers, or the LZB impact; from the
// moving geometry (`moving`), the frozen one too.
std::string faster_strikers_advice(bool moving);

// Throws InvalidInput naming `field` (a striker's gap, m) unless it is at most kFarthestGap
// times `reach`, the sum of the striker's and its target's radii (m): farther, the rounding of
// the striker's flight, gap x 2.2e-16, nears the contacts' touching tolerance, 1e-9 of the radii
// (a gap of 1e300 m ended on a singular contact problem, one of 1e308 on an infinite end time).
constexpr double kFarthestGap = 1e6;
void check_striker_gap(double gap, double reach, const std::string& field);

// Throws InvalidInput naming `field` unless the principal impulse step delta_p (N s) can
// resolve the impact: finite, below the smallest momentum m V (a coarser step resolves no
// approach, so the strikers would pass through their targets), and not so fine that the
// impact needs more than max_steps steps (it takes at least the largest momentum over
// delta_p).
void check_delta_p(const ContactModel& model, double delta_p, std::int64_t max_steps,
                   const std::string& field);

}  // namespace mimpact::granular
