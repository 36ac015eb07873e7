// The moving geometry's contacts with friction (Hertz, Mindlin's tangential spring under
// Coulomb's cap, spins; docs/friction.md, section 3) against LAMMPS's `pair_style granular` and
// `fix wall/gran granular` with `tangential mindlin` at their finest step: a steel sphere
// striking a sphere at rest and a wall obliquely, with and without spins; and the conservation
// of momentum and angular momentum.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "mimpact/granular/moving_contacts.hpp"
#include "steel_beads.hpp"

namespace mimpact::granular {
namespace {

constexpr double kFriction = 0.3;

// LAMMPS's runs, one case a line (tests/data/lammps/README.md).
std::vector<std::vector<double>> lammps_cases(const std::string& name, std::size_t fields) {
  std::ifstream file(std::string(MIMPACT_SOURCE_DIR) + "/tests/data/lammps/" + name);
  std::string line;
  std::getline(file, line);  // header
  std::vector<std::vector<double>> cases;
  while (std::getline(file, line)) {
    std::stringstream in(line);
    std::vector<double>& values = cases.emplace_back();
    for (std::string field; std::getline(in, field, ',');) values.push_back(std::stod(field));
    if (values.size() != fields)
      throw std::runtime_error(name + ": not " + std::to_string(fields) + " fields: " + line);
  }
  return cases;
}

// Steel beads in space whose contacts rub (mu 0.3, Mindlin's spring).
BeadGeometry rough_beads(const std::vector<Eigen::Vector3d>& positions) {
  BeadGeometry g = steel_beads(positions, 3);
  g.shape.friction = kFriction;
  return g;
}

MovingContactsOptions tight() {
  MovingContactsOptions options;
  options.ode.relative_tolerance = 1e-12;
  options.ode.absolute_tolerance = 1e-19;
  options.ode.event_tolerance = 1e-15;
  options.overlap_resolution = 1e-15;
  return options;
}

Eigen::Vector3d at(const std::vector<double>& c, std::size_t first) {
  return {c[first], c[first + 1], c[first + 2]};
}

// the larger of |v - v_ref| and r |w - w_ref| (m/s)
double difference(const MovingContacts& motion, Eigen::Index body, const Eigen::Vector3d& v,
                  const Eigen::Vector3d& w) {
  return std::max((motion.velocity(body) - v).cwiseAbs().maxCoeff(),
                  kRadius * (motion.angular_velocity(body) - w).cwiseAbs().maxCoeff());
}

// A steel sphere striking one at rest at 1 m/s, incidence 0 to 85 degrees from the line of
// centres, without spin and with a sideways velocity and spins of both: both spheres' v and
// r omega after the impact within 1e-8 of V of LAMMPS's at dt = 1.5625e-10 s; momentum kept to
// 1e-13 of the striker's, angular momentum about the origin to 1e-12 (the steps that amend a
// slipping spring move the bodies by what its missed impulse would have: to the steps' order,
// 3.3e-13 here, as in the plane), and the kinetic energy lost (e = 1) the tangential force's
// work to 1e-10.
TEST(MovingMindlin, TwoSpheresMeetLammps) {
  const auto cases = lammps_cases("sphere_on_sphere_mindlin.csv", 22);
  ASSERT_EQ(cases.size(), 36u);
  const double m = bead_mass(kRadius, kSteel), inertia = 0.4 * m * kRadius * kRadius;
  double worst = 0.0, worst_momentum = 0.0, worst_angular = 0.0, worst_ledger = 0.0;
  for (const auto& c : cases) {
    const BeadGeometry geometry = rough_beads({{0.0, 0.0, -2.0 * kRadius}, {0.0, 0.0, 0.0}});
    const std::vector<Eigen::Vector3d> velocity = {at(c, 1), Eigen::Vector3d::Zero()};
    const std::vector<Eigen::Vector3d> spin = {at(c, 4), at(c, 7)};
    MovingContacts motion(geometry, velocity, {}, tight(), spin);
    motion.advance(8e-5);
    const double error = std::max(difference(motion, 0, at(c, 10), at(c, 13)),
                                  difference(motion, 1, at(c, 16), at(c, 19)));
    worst = std::max(worst, error);
    EXPECT_LT(error, 1e-8) << "incidence " << c[0] << ", spin " << c[4];
    // momentum and angular momentum about the origin
    Eigen::Vector3d momentum = -m * velocity[0], moment = Eigen::Vector3d::Zero();
    for (Eigen::Index b = 0; b < 2; ++b) {
      moment += m * geometry.position[std::size_t(b)].cross(velocity[std::size_t(b)]) +
                inertia * spin[std::size_t(b)];
      momentum += m * motion.velocity(b);
      moment -=
          m * motion.position(b).cross(motion.velocity(b)) + inertia * motion.angular_velocity(b);
    }
    worst_momentum = std::max(worst_momentum, momentum.norm() / m);
    worst_angular = std::max(worst_angular, moment.norm() / (m * kRadius));
    // e = 1: what the bodies lost, the tangential force took
    const double before = 0.5 * m * velocity[0].squaredNorm() +
                          0.5 * inertia * (spin[0].squaredNorm() + spin[1].squaredNorm());
    worst_ledger = std::max(
        worst_ledger,
        std::abs(before - motion.kinetic_energy() - motion.contacts()[0].slip_work) / before);
  }
  std::printf(
      "two spheres, Hertz-Mindlin in the moving geometry, 36 strikes against LAMMPS: "
      "worst %.2e of V; momentum kept to %.1e, angular momentum to %.1e; energy lost less the "
      "slip's work %.1e of the energy\n",
      worst, worst_momentum, worst_angular, worst_ledger);
  EXPECT_LT(worst_momentum, 1e-13);
  EXPECT_LT(worst_angular, 1e-12);
  EXPECT_LT(worst_ledger, 1e-10);
}

// The same sphere striking a wall z = 0 (a wall of its material, as LAMMPS's explicit kn and
// kt): within 1e-8 of V of LAMMPS's `fix wall/gran`.
TEST(MovingMindlin, SphereOnAWallMeetsLammps) {
  const auto cases = lammps_cases("sphere_on_wall_mindlin.csv", 13);
  ASSERT_EQ(cases.size(), 36u);
  double worst = 0.0;
  for (const auto& c : cases) {
    BeadGeometry geometry = rough_beads({{0.0, 0.0, kRadius}});
    geometry.walls = {Plane{.point = Eigen::Vector3d::Zero(), .normal = Eigen::Vector3d::UnitZ()}};
    geometry.wall_material = {kSteel};
    MovingContacts motion(geometry, {at(c, 1)}, {}, tight(), {at(c, 4)});
    motion.advance(8e-5);
    const double error = difference(motion, 0, at(c, 7), at(c, 10));
    worst = std::max(worst, error);
    EXPECT_LT(error, 1e-8) << "incidence " << c[0] << ", spin " << c[4];
  }
  std::printf(
      "a sphere on a wall in the moving geometry, 36 strikes against LAMMPS: worst %.2e "
      "of V\n",
      worst);
}

}  // namespace
}  // namespace mimpact::granular
