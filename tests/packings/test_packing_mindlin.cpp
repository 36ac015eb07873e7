// Packings whose contacts rub in the moving geometry (Hertz with Mindlin's tangential spring
// under Coulomb's cap, the beads spinning; docs/friction.md, section 3) against LAMMPS's
// `pair_style granular hertz ... tangential mindlin` at its finest step: the 10 x 10 hexagonal
// and the FCC 6 x 6 x 6 packings of steel beads struck at 1 m/s, mu = 0.3, to 0.3 ms.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "mimpact/granular/energy_ledger.hpp"
#include "packing_runs.hpp"

namespace mimpact::testing {
namespace {

// A LAMMPS table of three columns (vx,vy,vz or wx,wy,wz: m/s or rad/s, a row per body;
// tests/data/lammps/README.md)
Eigen::MatrixX3d lammps_table(const std::string& name) {
  std::ifstream file(std::string(MIMPACT_SOURCE_DIR) + "/tests/data/lammps/" + name);
  std::string line;
  std::getline(file, line);  // its header
  std::vector<double> values;
  double x, y, z;
  while (std::getline(file, line)) {
    if (std::sscanf(line.c_str(), "%lf,%lf,%lf", &x, &y, &z) != 3)
      throw std::runtime_error(name + ": not three numbers: " + line);
    values.insert(values.end(), {x, y, z});
  }
  return Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      values.data(), Eigen::Index(values.size() / 3), 3);
}

// The 10 x 10 hexagonal packing of steel beads struck at 1 m/s, mu = 0.3, to 0.3 ms, at
// `tolerance`: the scene of LAMMPS's data.
PackingCase hexagonal_10x10(double tolerance) {
  char rest[160];
  std::snprintf(rest, sizeof rest,
                R"("contact": {"restitution": 1, "friction": 0.3}, "method": "compliant", )"
                R"("compliant": {"tolerance": %g, "end_time": 3e-4})",
                tolerance);
  return run_packing(lattice_scene("hexagonal", 10, 10, "[0, 5]", "[0, 1]", rest));
}

// The RMS and the worst over the bodies of the larger of |v - v_LAMMPS| and r |w - w_LAMMPS|,
// of V = 1 m/s, against LAMMPS's tables `name`_v_at_0.3ms.csv and `name`_w_at_0.3ms.csv.
struct Errors {
  double rms = 0.0, worst = 0.0;
};
Errors against_lammps(const PackingCase& run, const std::string& name) {
  const Eigen::MatrixX3d v_lammps = lammps_table(name + "_v_at_0.3ms.csv");
  const Eigen::MatrixX3d w_lammps = lammps_table(name + "_w_at_0.3ms.csv");
  EXPECT_EQ(v_lammps.rows(), run.model.body_count());
  const int d = run.model.dimension, spins = d == 3 ? 3 : 1;
  const Eigen::VectorXd& v = run.run.impact.velocity_after;
  const Eigen::VectorXd& w = run.run.impact.angular_velocity_after;
  Errors errors;
  for (Eigen::Index b = 0; b < v_lammps.rows(); ++b) {
    const Eigen::VectorXd w_b = w_lammps.row(b).tail(spins).transpose();
    const double error =
        std::max((v.segment(d * b, d) - v_lammps.row(b).head(d).transpose()).norm(),
                 0.005 * (w.segment(spins * b, spins) - w_b).norm());
    errors.rms += error * error;
    errors.worst = std::max(errors.worst, error);
  }
  errors.rms = std::sqrt(errors.rms / double(v_lammps.rows()));
  return errors;
}
constexpr char kHexagonal[] = "hexagonal_10x10_mu0.3";

// Its momentum's, its angular momentum's about the origin (the bodies where the run left them,
// as the summary takes it) and its energy's less the slip's work drifts, relative.
struct Drifts {
  double momentum = 0.0, angular_momentum = 0.0, energy = 0.0;
};
Drifts drifts(const PackingCase& run) {
  const packings::PackingModel& model = run.model;
  const granular::ImpactOutcome& impact = run.run.impact;
  const Eigen::VectorXd &v = impact.velocity_after, &w = impact.angular_velocity_after;
  EXPECT_EQ(impact.position_after.size(), v.size());
  const double t = impact.impact_time;
  const Eigen::VectorXd L0 =
      packings::angular_momentum(model, model.velocity, model.rotation->angular_velocity, t);
  const Eigen::VectorXd L1 = packings::angular_momentum(model, v, w, t, impact.position_after);
  const Eigen::VectorXd p0 = packings::momentum(model, model.velocity);
  const granular::EnergyLedger ledger = granular::energy_ledger(model, impact);
  return {(packings::momentum(model, v) - p0).norm() / p0.norm(), (L1 - L0).norm() / L0.norm(),
          std::abs(ledger.imbalance()) / (ledger.kinetic_before + ledger.rotational_before)};
}

// Every body's v and r omega within RMS 1e-7 of V of LAMMPS's (whose own halving moves them by
// RMS 2e-8); its momentum and its angular momentum about the origin kept to 1e-12, its energy
// less the slip's work to the tolerance's order.
TEST(PackingMindlin, HexagonalPackingMeetsLammps) {
  const PackingCase moving = hexagonal_10x10(1e-10);
  const Errors errors = against_lammps(moving, kHexagonal);
  std::printf(
      "10 x 10 hexagonal, mu 0.3, moving geometry against LAMMPS: RMS %.2e, worst %.2e of "
      "V\n",
      errors.rms, errors.worst);
  EXPECT_LT(errors.rms, 1e-7);
  const auto [momentum_drift, angular_drift, imbalance] = drifts(moving);
  std::printf(
      "momentum kept to %.1e, angular momentum about the origin to %.1e, energy less the slip's "
      "work to %.1e\n",
      momentum_drift, angular_drift, imbalance);
  EXPECT_LT(momentum_drift, 1e-12);
  EXPECT_LT(angular_drift, 1e-12);
  EXPECT_LT(imbalance, 2e-8);
}

// A planar group's springs are born, start and stop slipping within its steps: each spring
// that switches within a step is integrated again along the step with its switches located,
// and the step amended by what its stages missed (docs/design/moving_geometry.md, "Friction
// within a step"). The error against LAMMPS falls with the tolerance (at least 2.5 times a
// decade, and within 10 times the tolerance) in fewer steps than 8 tol^-0.3 (before the
// amendment: 5 922 at 1e-6, 9 895 at 1e-7); momentum stays exact, the angular momentum and the
// energy ledger to the tolerance's order.
TEST(PackingMindlin, StepsAcrossSwitchesConvergeWithTheTolerance) {
  double previous = 1.0;
  for (double tolerance : {1e-6, 1e-7, 1e-8}) {
    const PackingCase run = hexagonal_10x10(tolerance);
    const Errors errors = against_lammps(run, kHexagonal);
    const granular::MovingContactsStats& work = run.run.moving;
    const auto [momentum_drift, angular_drift, imbalance] = drifts(run);
    std::printf(
        "tolerance %g: RMS %.2e, worst %.2e of V against LAMMPS; %lld steps, %lld springs "
        "amended at a switch; momentum kept to %.1e, angular momentum to %.1e, energy less the "
        "slip's work to %.1e\n",
        tolerance, errors.rms, errors.worst, static_cast<long long>(work.steps),
        static_cast<long long>(work.amended_springs), momentum_drift, angular_drift, imbalance);
    EXPECT_LT(errors.rms, 10.0 * tolerance);
    EXPECT_LT(errors.rms, previous / 2.5);
    EXPECT_GT(work.amended_springs, 0);
    EXPECT_LT(double(work.steps), 8.0 * std::pow(tolerance, -0.3));
    EXPECT_LT(momentum_drift, 1e-12);
    EXPECT_LT(angular_drift, 1e-3 * tolerance);  // the steps' own order, as without friction
    EXPECT_LT(imbalance, 20.0 * tolerance);
    previous = errors.rms;
  }
}

// The FCC 6 x 6 x 6 packing of steel beads struck from below at bead (0, 3, 3) at 1 m/s, mu =
// 0.3, to 0.3 ms: in space every spring that slips within a step is integrated again along it
// (numerics::mindlin::SpatialPlay), its direction turning toward the slip's at |s| / r_c,
// which the stages cannot follow near a spring's birth (before: 342 218 steps and 144 s at
// tolerance 1e-7). Its v and r omega within RMS 1e-7 of V of LAMMPS's (whose own halving
// moves them by RMS 2.2e-8) at tolerance 1e-9, in fewer than 2 000 steps (tolerance 1e-8 meets
// it too, at RMS 4.5e-8); momentum and angular momentum about the origin kept to 1e-12, the
// energy ledger to the tolerance's order (27 times it).
TEST(PackingMindlin, FccPackingMeetsLammps) {
  const PackingCase run = run_packing("{" + kSteel + R"(, "lattice": {"type": "fcc", "layers": 6,
      "rows": 6, "columns": 6, "radius": 0.005}, "strikers": [{"target": [0, 3, 3], "radius":
      0.005, "velocity": [0, 0, 1]}], "contact": {"restitution": 1, "friction": 0.3}, "method":
      "compliant", "compliant": {"tolerance": 1e-9, "end_time": 3e-4}})");
  const Errors errors = against_lammps(run, "fcc_6x6x6_mu0.3");
  const auto [momentum_drift, angular_drift, imbalance] = drifts(run);
  std::printf(
      "FCC 6^3, mu 0.3, tolerance 1e-9, against LAMMPS: RMS %.2e, worst %.2e of V; %lld steps, "
      "%lld springs amended; momentum kept to %.1e, angular momentum to %.1e, energy less the "
      "slip's work to %.1e\n",
      errors.rms, errors.worst, static_cast<long long>(run.run.moving.steps),
      static_cast<long long>(run.run.moving.amended_springs), momentum_drift, angular_drift,
      imbalance);
  EXPECT_LT(errors.rms, 1e-7);
  EXPECT_LT(run.run.moving.steps, 2000);
  EXPECT_LT(momentum_drift, 1e-12);
  EXPECT_LT(angular_drift, 1e-12);
  EXPECT_LT(imbalance, 50.0 * 1e-9);
}

// contact.pairs in the moving geometry: a glass bead sent sliding along a felt floor (mu 0.8)
// and a steel striker off-centre on a glass bead far from it (mu 0.2), in one scene whose
// contact.friction (0.05) neither takes; the two rubbing contacts never meet, so each body leaves
// as in the same scene with contact.friction its own pair's mu for every contact.
TEST(PackingMindlin, FrictionPerPairOfMaterials) {
  const auto directory = std::filesystem::temp_directory_path() / "mimpact_test_mindlin_pairs";
  std::filesystem::create_directories(directory);
  std::ofstream(directory / "pair.csv")
      << "x,y,radius,vx,vy,wz\n0,0.005,0.005,0.6,-0.8,0\n0.1,0.05,0.005,0,0,0\n";
  auto scene = [&](const std::string& contact) {
    return R"({"beads": {"file": "pair.csv", "material": {"name": "glass", "density": 2500,
        "young": 6e10, "poisson": 0.2}}, "walls": [{"side": "bottom", "material": {"name":
        "felt", "density": 1000, "young": 1e9, "poisson": 0.3}}], "strikers": [{"target": [1],
        "radius": 0.005, "velocity": [1, 0], "offset": 0.004, "gap": 0.001, "material": {"name":
        "steel", "density": 7780, "young": 2.03e11, "poisson": 0.3}}], "contact": )" +
           contact + R"(, "method": "compliant", "compliant": {"tolerance": 1e-10,
        "end_time": 2e-3}, "configuration_check": {"enabled": false}})";
  };
  const PackingCase pairs = run_packing(
      scene(R"({"friction": 0.05, "pairs": [{"materials": ["felt", "glass"], "friction": 0.8},
          {"materials": ["glass", "steel"], "friction": 0.2}]})"),
      directory.string());
  const PackingCase felt = run_packing(scene(R"({"friction": 0.8})"), directory.string());
  const PackingCase steel = run_packing(scene(R"({"friction": 0.2})"), directory.string());
  // (v, r omega) of body b against the same body of run `alone`, of V = 1 m/s
  auto difference = [&](Eigen::Index b, const PackingCase& alone) {
    const granular::ImpactOutcome &x = pairs.run.impact, &y = alone.run.impact;
    return std::max(
        (x.velocity_after.segment<2>(2 * b) - y.velocity_after.segment<2>(2 * b)).norm(),
        0.005 * std::abs(x.angular_velocity_after(b) - y.angular_velocity_after(b)));
  };
  const double worst = std::max({difference(0, felt), difference(1, steel), difference(2, steel)});
  // and the scene's own mu would have left the bead on felt otherwise
  const PackingCase slick = run_packing(scene(R"({"friction": 0.05})"), directory.string());
  const double apart = difference(0, slick);
  std::printf(
      "per-pair mu in the moving geometry: each body as with its pair's mu everywhere to %.2e "
      "of V, %.3f m/s from contact.friction's\n",
      worst, apart);
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(apart, 0.01);
}

}  // namespace
}  // namespace mimpact::testing
