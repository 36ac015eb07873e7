// The work of the moving geometry follows what moves (issue 24, item c): the time steps its
// bodies take, per contact that carried force and per second of the run, do not grow with the
// packing. Counts, not timings: the timings are bench/bench_packing_peers.cpp's
// (docs/performance_packings.md).
#include <gtest/gtest.h>

#include <cstdio>

#include "packing_runs.hpp"

namespace mimpact::testing {
namespace {

// body steps / (contacts loaded x duration), for a hexagonal side x side packing struck at the
// middle of its bottom edge at 1 m/s and run to just after the front has crossed
double steps_per_contact_second(int side) {
  const double end_time = side * 3.1e-5;  // s: the front crosses 100 rows in 3.1 ms
  const PackingCase packing = run_packing(
      lattice_scene("hexagonal", side, side, "[0, " + std::to_string(side / 2) + "]", "[0.0, 1.0]",
                    R"("method": "compliant", "compliant": {"tolerance": 1e-4, "end_time": )" +
                        std::to_string(end_time) + "}"));
  const granular::MovingContactsStats& work = packing.run.moving;
  EXPECT_GT(work.contacts_loaded, side * side) << side;  // the front crossed: most contacts
  return double(work.member_steps) / (double(work.contacts_loaded) * end_time);
}

// A group-wide step resolving every closing of the front would make each step shorter as the
// front widens, and the work per contact grow with the side (twofold from 16 to 32 for a front
// twice as wide). Measured: 7.6e4 and 7.1e4 body steps per contact and second (7.7e4 on
// 100 x 100, 6.9e4 on 56 x 56). What a step costs beyond its bodies' right-hand sides (the
// windows' groups, the peaks) is the benchmark's to measure.
TEST(PackingCost, BodyStepsPerLoadedContactAndSecondDoNotGrowWithThePacking) {
  const double small = steps_per_contact_second(16), large = steps_per_contact_second(32);
  std::printf("body steps per contact and second: 16 x 16 %.3g, 32 x 32 %.3g\n", small, large);
  EXPECT_LT(large, 1.25 * small);
}

}  // namespace
}  // namespace mimpact::testing
