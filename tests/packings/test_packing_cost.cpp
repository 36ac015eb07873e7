// The work of the moving geometry follows what moves (issue 24, item c): the time steps its
// bodies take, per contact that carried force and per second of the run, do not grow with the
// packing. Counts, not timings: the timings are bench/bench_packing_peers.cpp's
// (docs/performance_packings.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "packing_runs.hpp"

namespace mimpact::testing {
namespace {

// The work of a hexagonal side x side packing struck at the middle of its bottom edge at 1 m/s
// and run to just after the front has crossed: body steps / (contacts loaded x duration), and
// the bodies its groups' restarts carried per body step.
struct Work {
  double steps_per_contact_second, restarts_per_step;
};
Work packing_work(int side) {
  const double end_time = side * 3.1e-5;  // s: the front crosses 100 rows in 3.1 ms
  const PackingCase packing = run_packing(
      lattice_scene("hexagonal", side, side, "[0, " + std::to_string(side / 2) + "]", "[0.0, 1.0]",
                    R"("method": "compliant", "compliant": {"tolerance": 1e-4, "end_time": )" +
                        std::to_string(end_time) + "}"));
  const granular::MovingContactsStats& work = packing.run.moving;
  EXPECT_GT(work.contacts_loaded, side * side) << side;  // the front crossed: most contacts
  return {double(work.member_steps) / (double(work.contacts_loaded) * end_time),
          double(work.member_restarts) / double(work.member_steps)};
}

// A group-wide step resolving every closing of the front would make each step shorter as the
// front widens, and the work per contact grow with the side (twofold from 16 to 32 for a front
// twice as wide). Measured: 1.37e5 and 9.12e4 body steps per contact and second. A group that
// restarts to take each body its halo missed restarts more often the larger it is, each
// restart costing about half a step of all its bodies: 32 x 32 restarted 4.7 % of its body
// steps' bodies, 100 x 100 39 %, before the halo took the bodies its own bodies meet
// (docs/model.md, section 17); now 1.5e-5 and 2.0 %. What a step costs beyond its bodies'
// right-hand sides (the windows' groups, the peaks) is the benchmark's to measure.
TEST(PackingCost, BodyStepsPerLoadedContactAndSecondDoNotGrowWithThePacking) {
  const Work small = packing_work(16), large = packing_work(32);
  std::printf(
      "body steps per contact and second: 16 x 16 %.3g, 32 x 32 %.3g; bodies restarted per body "
      "step %.3g and %.3g\n",
      small.steps_per_contact_second, large.steps_per_contact_second, small.restarts_per_step,
      large.restarts_per_step);
  EXPECT_LT(large.steps_per_contact_second, 1.25 * small.steps_per_contact_second);
  EXPECT_LT(small.restarts_per_step, 0.01);
  EXPECT_LT(large.restarts_per_step, 0.01);
}

// A window that one group integrates may outlast the bound that keeps two groups from meeting
// unseen within one (docs/model.md, section 17): an FCC 6^3 packing struck at 1 m/s takes such
// windows at tolerance 3e-3, and its velocities stay within 1e-4 of the run at 1e-10,
// whose short steps keep every window short, with its momentum kept to round-off.
TEST(PackingCost, AWindowOfOneGroupOutlastsTwoGroupsBoundAndKeepsTheAnswer) {
  constexpr double kLoose = 3e-3;
  auto run = [](double tolerance) {
    char compliant[120];
    std::snprintf(compliant, sizeof compliant,
                  R"("method": "compliant", "compliant": {"tolerance": %g, "end_time": 1.5e-4})",
                  tolerance);
    return run_packing("{" + kSteel +
                       R"(, "lattice": {"type": "fcc", "layers": 6, "rows": 6, "columns": 6,
                          "radius": 0.005}, "strikers": [{"target": [0, 3, 3], "radius": 0.005,
                          "velocity": [0, 0, 1]}], )" +
                       compliant + "}");
  };
  const PackingCase loose = run(kLoose), fine = run(1e-10);
  const Eigen::VectorXd& v = loose.run.impact.velocity_after;
  const Eigen::VectorXd& reference = fine.run.impact.velocity_after;
  const Eigen::Index bodies = loose.model.body_count();
  double sum = 0.0, worst = 0.0;
  Eigen::Vector3d before = Eigen::Vector3d::Zero(), after = Eigen::Vector3d::Zero();
  for (Eigen::Index b = 0; b < bodies; ++b) {
    const double error = (v.segment<3>(3 * b) - reference.segment<3>(3 * b)).norm();
    sum += error * error;
    worst = std::max(worst, error);
    before += loose.model.mass(3 * b) * loose.model.velocity.segment<3>(3 * b);
    after += loose.model.mass(3 * b) * v.segment<3>(3 * b);
  }
  const double rms = std::sqrt(sum / double(bodies));  // relative to the striker's 1 m/s
  std::printf(
      "windows beyond two groups' bound: %lld of %lld at %g (%lld at 1e-10); RMS %.3g, worst "
      "%.3g m/s\n",
      (long long)loose.run.moving.extended_windows, (long long)loose.run.moving.windows, kLoose,
      (long long)fine.run.moving.extended_windows, rms, worst);
  EXPECT_GT(loose.run.moving.extended_windows, 0);
  EXPECT_EQ(fine.run.moving.extended_windows, 0);
  EXPECT_LT(rms, 1e-4);
  EXPECT_LT((after - before).norm(), 1e-12 * before.norm());
}

}  // namespace
}  // namespace mimpact::testing
