// Packings whose contacts rub in the moving geometry (Hertz with Mindlin's tangential spring
// under Coulomb's cap, the beads spinning; docs/friction.md, section 3) against LAMMPS's
// `pair_style granular hertz ... tangential mindlin` at its finest step: the 10 x 10 hexagonal
// packing of steel beads struck at 1 m/s, mu = 0.3, to 0.3 ms.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "packing_runs.hpp"

namespace mimpact::testing {
namespace {

// LAMMPS's angular velocities about z (rad/s, a row per body; tests/data/lammps/README.md)
Eigen::VectorXd lammps_spins(const std::string& name) {
  std::ifstream file(std::string(MIMPACT_SOURCE_DIR) + "/tests/data/lammps/" + name);
  std::string line;
  std::getline(file, line);  // wx,wy,wz
  std::vector<double> values;
  double wx, wy, wz;
  while (std::getline(file, line)) {
    if (std::sscanf(line.c_str(), "%lf,%lf,%lf", &wx, &wy, &wz) != 3)
      throw std::runtime_error(name + ": not wx,wy,wz: " + line);
    values.push_back(wz);
  }
  return Eigen::Map<Eigen::VectorXd>(values.data(), Eigen::Index(values.size()));
}

// Every body's v and r omega within RMS 1e-7 of V of LAMMPS's (whose own halving moves them by
// RMS 2e-8), the run's energy ledger balanced: the kinetic energy lost is what the contacts
// hold and took, the slip's share included.
TEST(PackingMindlin, HexagonalPackingMeetsLammps) {
  const PackingCase moving = run_packing(
      lattice_scene("hexagonal", 10, 10, "[0, 5]", "[0, 1]",
                    R"("contact": {"restitution": 1, "friction": 0.3}, "method": "compliant",
         "compliant": {"tolerance": 1e-10, "end_time": 3e-4})"));
  const Eigen::MatrixX2d v_lammps = lammps_velocities("hexagonal_10x10_mu0.3_v_at_0.3ms.csv");
  const Eigen::VectorXd w_lammps = lammps_spins("hexagonal_10x10_mu0.3_w_at_0.3ms.csv");
  ASSERT_EQ(v_lammps.rows(), moving.model.body_count());
  const Eigen::VectorXd& v = moving.run.impact.velocity_after;
  const Eigen::VectorXd& w = moving.run.impact.angular_velocity_after;
  double squares = 0.0, worst = 0.0;
  for (Eigen::Index b = 0; b < v_lammps.rows(); ++b) {
    const double error = std::max((v.segment<2>(2 * b) - v_lammps.row(b).transpose()).norm(),
                                  0.005 * std::abs(w(b) - w_lammps(b)));
    squares += error * error;
    worst = std::max(worst, error);
  }
  const double rms = std::sqrt(squares / double(v_lammps.rows()));
  std::printf(
      "10 x 10 hexagonal, mu 0.3, moving geometry against LAMMPS: RMS %.2e, worst %.2e of "
      "V\n",
      rms, worst);
  EXPECT_LT(rms, 1e-7);
}

}  // namespace
}  // namespace mimpact::testing
