// The work follows the wave (issue 10, item 3): on C1's beads, the adaptive LZB integrates only
// the contacts in the impact and the compliant method only the bodies in contact, so ten times
// the beads cost ten times the steps and no more per step; a looser tolerance never costs more.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "../support/chain_runs.hpp"
#include "mimpact/granular/impact_recorder.hpp"

namespace mimpact::testing {
namespace {

// C1's beads and striker, `beads` long.
chains::ChainModel c1_beads(int beads) {
  chains::ChainScene scene =
      chains::load_chain_scene(std::string(MIMPACT_SOURCE_DIR) + "/examples/scenes/c1.json");
  scene.chain.segments[0].count = beads;
  return chains::build_chain_model(scene);
}

// The wave forms within 2e-4 s and crosses a bead in 3.2e-5 s: the compliant run ends after it
// has left (behind it the beads come to rest touching, so the contacts never all open).
granular::CompliantRun run_compliant(const chains::ChainModel& model, double tolerance) {
  granular::CompliantSpec spec;
  spec.tolerance = tolerance;
  spec.end_time = 2e-4 + 3.2e-5 * double(model.body_count());
  return chains::simulate_chain_compliant(model, spec, {});
}

TEST(WaveCost, TenTimesTheBeadsCostTenTimesTheStepsAndTheSameWorkPerStep) {
  const chains::ChainModel short_chain = c1_beads(300), long_chain = c1_beads(3000);
  const granular::CompliantRun compliant_short = run_compliant(short_chain, 1e-6);
  const granular::CompliantRun compliant_long = run_compliant(long_chain, 1e-6);
  const double compliant_ratio =
      double(compliant_long.impact.result.steps) / double(compliant_short.impact.result.steps);
  std::printf(
      "compliant at 1e-6: %lld and %lld steps (x%.2f), at most %lld and %lld bodies "
      "integrated at once\n",
      (long long)compliant_short.impact.result.steps, (long long)compliant_long.impact.result.steps,
      compliant_ratio, (long long)compliant_short.most_bodies_in_motion,
      (long long)compliant_long.most_bodies_in_motion);
  EXPECT_LE(compliant_ratio, 10.5);
  // the wave is a few beads wide, whatever the chain's length
  EXPECT_LE(compliant_long.most_bodies_in_motion, 12);
  EXPECT_EQ(compliant_long.most_bodies_in_motion, compliant_short.most_bodies_in_motion);

  const granular::ImpactOutcome adaptive_short = run_adaptive(short_chain, 1e-6);
  const granular::ImpactOutcome adaptive_long = run_adaptive(long_chain, 1e-6);
  const double adaptive_ratio =
      double(adaptive_long.result.steps) / double(adaptive_short.result.steps);
  const double contacts_per_step =
      double(adaptive_long.result.contact_steps) / double(adaptive_long.result.steps);
  std::printf("adaptive at 1e-6: %lld and %lld steps (x%.2f), %.2f contacts per step\n",
              (long long)adaptive_short.result.steps, (long long)adaptive_long.result.steps,
              adaptive_ratio, contacts_per_step);
  EXPECT_LE(adaptive_ratio, 10.5);
  EXPECT_LE(contacts_per_step, 12.0);
  // the two methods see the same wave leave the chain
  const Eigen::Index last = long_chain.body_count() - 1;
  EXPECT_NEAR(compliant_long.impact.velocity_after(last), adaptive_long.velocity_after(last),
              2e-4 * long_chain.velocity(0));
}

// Behind the wave the beads stand touching, approaching each other at the integration's own
// error speeds. Those collisions are taken as instantaneous (slower than the tolerance times
// the striker's speed), so they cost no integration: at 30 000 beads and tolerance 1e-8 at most
// a handful of bodies move at once (140 s and a thousand bodies in motion when they were
// integrated), and the last bead leaves at the adaptive LZB's speed to 1e-6 (measured 1.3e-7
// at tolerance 1e-9 against the adaptive run at 1e-10).
TEST(WaveCost, TheWakesSlowCollisionsCostNoIntegration) {
  const chains::ChainModel model = c1_beads(30000);
  const granular::CompliantRun compliant = run_compliant(model, 1e-8);
  const granular::ImpactOutcome adaptive = run_adaptive(model, 1e-9);
  const Eigen::Index last = model.body_count() - 1;
  std::printf(
      "30 000 beads: compliant at 1e-8, %lld steps, at most %lld bodies in motion; last "
      "bead %.9f against %.9f (adaptive at 1e-9)\n",
      (long long)compliant.impact.result.steps, (long long)compliant.most_bodies_in_motion,
      compliant.impact.velocity_after(last), adaptive.velocity_after(last));
  EXPECT_LE(compliant.most_bodies_in_motion, 12);
  EXPECT_NEAR(compliant.impact.velocity_after(last), adaptive.velocity_after(last), 2e-6);
  const granular::EnergyLedger ledger = granular::energy_ledger(model, compliant.impact);
  EXPECT_LE(std::abs(ledger.imbalance()), 1e-12 * ledger.kinetic_before);
}

// Issue 10 (g): the report for people summarizes a long chain in a few lines: its ends, its
// extremes and its energy, with every velocity left to summary.json.
TEST(WaveCost, ALongChainsReportStaysShort) {
  const chains::ChainModel model = c1_beads(3000);
  const granular::ImpactOutcome impact = run_adaptive(model, 1e-6);
  const std::string report = chains::chain_report(model, impact, "adaptive, tolerance 1e-06");
  std::printf("%s", report.c_str());
  EXPECT_LE(std::count(report.begin(), report.end(), '\n'), 10);
  EXPECT_NE(report.find("kinetic energy"), std::string::npos);
  Eigen::Index fastest;
  impact.velocity_after.maxCoeff(&fastest);
  EXPECT_NE(report.find("(body " + std::to_string(fastest) + ")"), std::string::npos) << report;
  char last[32];
  std::snprintf(last, sizeof last, "%.5g\n", impact.velocity_after(model.body_count() - 1));
  EXPECT_NE(report.find(last), std::string::npos) << report;
}

// Bodies in free flight cost no step: a striker 1 m from the chain flies to it in closed form.
TEST(WaveCost, FreeFlightCostsNoStep) {
  chains::ChainScene scene =
      chains::load_chain_scene(std::string(MIMPACT_SOURCE_DIR) + "/examples/scenes/c1.json");
  const chains::ChainModel touching = chains::build_chain_model(scene);
  scene.strikers[0].gap = 1.0;
  const chains::ChainModel far = chains::build_chain_model(scene);
  granular::CompliantSpec spec;
  spec.tolerance = 1e-8;
  spec.end_time = 1.0 + 2e-3;
  const granular::CompliantRun flown = chains::simulate_chain_compliant(far, spec, {});
  spec.end_time = 2e-3;
  const granular::CompliantRun struck = chains::simulate_chain_compliant(touching, spec, {});
  std::printf("striker 1 m away: %lld steps, touching: %lld steps; impact at t = %.12g s\n",
              (long long)flown.impact.result.steps, (long long)struck.impact.result.steps,
              flown.impact.impact_time);
  EXPECT_EQ(flown.impact.result.steps, struck.impact.result.steps);
  EXPECT_NEAR(flown.impact.impact_time, 1.0 / far.velocity(0), 1e-9);
  EXPECT_LE(relative_difference(flown.impact.velocity_after, struck.impact.velocity_after), 1e-9);
}

// A chain at rest stays at rest until the wave comes, at the finest tolerance too: 100 000 beads
// placed end to end reach 2 km, where the positions' round-off leaves 93 597 contacts
// overlapping by up to 1.8e-14 m, more than the joining overlap of a tolerance of 2e-13 or
// finer; taken as static loads, they set the whole chain in motion (1 244 steps of the first
// 3.6e-5 s took 87 s at 1e-13). Within the positions' round-off an overlap is a touch.
TEST(WaveCost, AChainAtRestStaysAtRestAtTheFinestTolerance) {
  const chains::ChainModel model = c1_beads(100'000);
  granular::CompliantSpec spec;
  spec.tolerance = 1e-14;
  spec.end_time = 1e-4;
  const granular::CompliantRun compliant = chains::simulate_chain_compliant(model, spec, {});
  std::printf("100 000 beads at tolerance 1e-14: %lld steps, at most %lld bodies in motion\n",
              (long long)compliant.impact.result.steps, (long long)compliant.most_bodies_in_motion);
  EXPECT_LE(compliant.most_bodies_in_motion, 12);
  EXPECT_EQ(compliant.impact.velocity_after.tail(model.body_count() - 12).cwiseAbs().maxCoeff(),
            0.0);
}

TEST(WaveCost, ALooserToleranceNeverCostsMore) {
  const chains::ChainModel model = c1_beads(300);
  std::int64_t compliant_before = 0, adaptive_before = 0;
  for (double tolerance : {1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10}) {
    const std::int64_t compliant = run_compliant(model, tolerance).impact.result.steps;
    const std::int64_t adaptive = run_adaptive(model, tolerance).result.steps;
    std::printf("tolerance %g: compliant %lld steps, adaptive %lld steps\n", tolerance,
                (long long)compliant, (long long)adaptive);
    EXPECT_GE(compliant, compliant_before) << tolerance;
    EXPECT_GE(adaptive, adaptive_before) << tolerance;
    compliant_before = compliant;
    adaptive_before = adaptive;
  }
}

// Behind the wave, too: the beads' positions, sums of radii, carry round-off that jumps where
// they cross some powers of two (2, 4, 16, 32 m: beads 100, 200, 800, 1 600), and gaps of
// that round-off (1e-14 m) are more than the joining overlap at the finest tolerances. Taken as
// gaps, they left the wake colliding at 1e-11 of V, above the speed of an instantaneous
// collision, in groups that stayed in motion ever after: 123 bodies in motion at 0.05 s at
// tolerance 4.8e-14 (202 s for 0.1 s of 100 000 beads). A gap within its positions' round-off is
// a touch.
TEST(WaveCost, TheWakeStaysAtRestAtTheFinestTolerance) {
  const chains::ChainModel model = c1_beads(2'000);
  granular::CompliantSpec spec;
  spec.tolerance = 4.8e-14;
  spec.end_time = 0.05;
  const granular::CompliantRun compliant = chains::simulate_chain_compliant(model, spec, {});
  Eigen::Index front;
  compliant.impact.velocity_after.maxCoeff(&front);
  const double wake =
      compliant.impact.velocity_after.segment(150, front - 180).cwiseAbs().maxCoeff();
  std::printf(
      "2 000 beads at tolerance 4.8e-14 to 0.05 s: %lld steps, at most %lld bodies in "
      "motion, the wave's front at bead %lld, the wake (beads 150 to %lld) at most %.3g "
      "m/s\n",
      (long long)compliant.impact.result.steps, (long long)compliant.most_bodies_in_motion,
      (long long)front, (long long)front - 30, wake);
  EXPECT_LE(compliant.most_bodies_in_motion, 12);
  // a solitary wave leaves the beads behind it at rest
  EXPECT_LE(wake, spec.tolerance * model.velocity(0));
}

}  // namespace
}  // namespace mimpact::testing
