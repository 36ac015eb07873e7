// The work of the moving geometry and of the adaptive LZB follows what moves (issue 24, item
// c): the time steps its bodies (contacts) take, per contact that carried force and per second
// of the run, do not grow with the packing. Counts, not timings: the timings are
// bench/bench_packing_peers.cpp's (docs/performance_packings.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "packing_runs.hpp"

namespace mimpact::testing {
namespace {

// The work of a packing struck at 1 m/s in the middle of its first row (or layer), at
// tolerance 1e-4, until just after the front has crossed: body steps / (contacts loaded x
// duration), and the bodies its groups' restarts carried per body step.
struct Work {
  double steps_per_contact_second, restarts_per_step;
};
std::string compliant_until(double end_time) {
  return R"("method": "compliant", "compliant": {"tolerance": 1e-4, "end_time": )" +
         std::to_string(end_time) + "}";
}
Work packing_work(const std::string& scene, double end_time, int beads) {
  const PackingCase packing = run_packing(scene);
  const granular::MovingContactsStats& work = packing.run.moving;
  EXPECT_GT(work.contacts_loaded, beads) << scene;  // the front crossed: most contacts
  return {double(work.member_steps) / (double(work.contacts_loaded) * end_time),
          double(work.member_restarts) / double(work.member_steps)};
}

// hexagonal side x side; the front crosses 100 rows in 3.1 ms
Work hexagonal_work(int side, double restitution = 1.0) {
  const double end_time = side * 3.1e-5;
  return packing_work(
      lattice_scene("hexagonal", side, side, "[0, " + std::to_string(side / 2) + "]", "[0.0, 1.0]",
                    R"("contact": {"model": "bi-stiffness", "exponent": 1.5, "restitution": )" +
                        std::to_string(restitution) + "}, " + compliant_until(end_time)),
      end_time, side * side);
}

// FCC side^3, struck along the layers' axis; the front crosses 20 layers in 0.5 ms
Work fcc_work(int side) {
  const double end_time = side * 2.5e-5;
  const std::string n = std::to_string(side), middle = std::to_string(side / 2);
  return packing_work("{" + kSteel + R"(, "lattice": {"type": "fcc", "layers": )" + n +
                          R"(, "rows": )" + n + R"(, "columns": )" + n +
                          R"(, "radius": 0.005}, "strikers": [{"target": [0, )" + middle + ", " +
                          middle + R"(], "radius": 0.005, "velocity": [0, 0, 1]}], )" +
                          compliant_until(end_time) + "}",
                      end_time, side * side * side);
}

// The larger packing's work per loaded contact and second is no more than the smaller's, give
// or take a quarter, and restarts carry under 1 % of the body steps' bodies.
void expect_work_follows_what_moves(const char* small_name, const Work& small,
                                    const char* large_name, const Work& large) {
  std::printf(
      "body steps per contact and second: %s %.3g, %s %.3g; bodies restarted per body step %.3g "
      "and %.3g\n",
      small_name, small.steps_per_contact_second, large_name, large.steps_per_contact_second,
      small.restarts_per_step, large.restarts_per_step);
  EXPECT_LT(large.steps_per_contact_second, 1.25 * small.steps_per_contact_second);
  EXPECT_LT(small.restarts_per_step, 0.01);
  EXPECT_LT(large.restarts_per_step, 0.01);
}

// A group-wide step resolving every closing of the front would make each step shorter as the
// front widens, and the work per contact grow with the side (twofold from 16 to 32 for a front
// twice as wide). Measured: 1.37e5 and 9.12e4 body steps per contact and second. A group that
// restarts to take each body its halo missed restarts more often the larger it is, each
// restart costing about half a step of all its bodies: 32 x 32 restarted 4.7 % of its body
// steps' bodies, 100 x 100 39 %, before the halo took the bodies its own bodies meet
// (docs/design/moving_geometry.md); now 1.5e-5 and 2.0 %. What a step costs beyond its bodies'
// right-hand sides (the windows' groups, the peaks) is the benchmark's to measure.
TEST(PackingCost, BodyStepsPerLoadedContactAndSecondDoNotGrowWithThePacking) {
  expect_work_follows_what_moves("16 x 16", hexagonal_work(16), "32 x 32", hexagonal_work(32));
}

// The same with inelastic contacts (e = 0.9), whose law turns at each one's largest overlap:
// found within the step and amended there, not a restart of the group (docs/model.md, section
// 17). Measured: 1.18e5 and 7.89e4 body steps per contact and second, restarts carrying 1.0e-4
// and 1.8e-5 of the body steps' bodies. Located, each turn, join and leave a restart of its
// group, 32 x 32 restarted 99 % of its body steps' bodies (10.0 M restarted, 10.1 M steps; 3.2 s
// at tolerance 1e-4 against 0.13 s now).
TEST(PackingCost, InelasticContactsTurnWithoutRestartingTheirGroup) {
  expect_work_follows_what_moves("16 x 16, e = 0.9", hexagonal_work(16, 0.9), "32 x 32",
                                 hexagonal_work(32, 0.9));
}

// The same in space: measured 1.79e5 and 8.45e4 body steps per contact and second on FCC 6^3
// and 12^3 (1.26e5 on 8^3, 6.25e4 on 16^3), restarts carrying 2.6e-4 and 2.5e-5 of the body
// steps' bodies.
TEST(PackingCost, InSpaceTooTheWorkPerLoadedContactDoesNotGrowWithThePacking) {
  expect_work_follows_what_moves("FCC 6^3", fcc_work(6), "12^3", fcc_work(12));
}

// The adaptive LZB on hexagonal packings struck at 1 m/s, tolerance 1e-6, the whole impact:
// contact steps (the contacts each Runge-Kutta step carries, summed) per contact that carried
// force and per second of the impact. Located one by one, every switch of any contact ended a
// step of all of them, and the steps grew with the contacts (measured for e = 1: 2.48e6 and
// 7.17e6 on 16 x 16 and 32 x 32, 0.51 s and 12.0 s; for e = 0.9: 1.89e6 and 5.53e6, 0.27 s and
// 9.3 s). Kept within the steps (docs/design/adaptive_lzb.md), for e = 1 4.61e5 and 3.23e5 (0.09 s
// and 0.76 s; 56 x 56 2.56e5, 100 x 100 1.94e5 in 25 s), for e = 0.9, where an expanding
// contact's delta goes at 1/e^2 its compression's rate, 4.02e5 and 2.66e5 (0.12 s and 0.92 s).
TEST(PackingCost, TheAdaptiveLzbsWorkPerReachedContactDoesNotGrowWithThePacking) {
  for (const double restitution : {1.0, 0.9}) {
    auto work = [&](int side) {
      const PackingCase packing = run_packing(lattice_scene(
          "hexagonal", side, side, "[0, " + std::to_string(side / 2) + "]", "[0.0, 1.0]",
          R"("contact": {"model": "bi-stiffness", "exponent": 1.5, "restitution": )" +
              std::to_string(restitution) + R"(},
             "impact": {"integrator": "adaptive", "tolerance": 1e-6},
             "configuration_check": {"enabled": false})"));
      const numerics::ImpactResult& impact = packing.run.impact.result;
      const auto reached = (impact.max_force.array() > 0.0).count();
      EXPECT_GT(reached, 2 * side * side);  // the wave crossed: most contacts
      // every contact reached switches at least twice (its peak, its release): fewer steps than
      // contacts reached, the switches were not each a step's end (measured 973 steps for 2 930
      // contacts on 32 x 32 at e = 0.9, 1 205 for 2 930 at e = 1)
      if (side >= 32) {
        EXPECT_LT(impact.steps, reached) << "e = " << restitution;
      }
      return double(impact.contact_steps) / (double(reached) * impact.duration);
    };
    const double small = work(16), large = work(32);
    std::printf(
        "e = %g: contact steps per reached contact and second: 16 x 16 %.3g, 32 x 32 %.3g\n",
        restitution, small, large);
    EXPECT_LT(large, small) << "e = " << restitution;
  }
}

// A window that one group integrates may outlast the bound that keeps two groups from meeting
// unseen within one (docs/design/moving_geometry.md): an FCC 6^3 packing struck at 1 m/s takes such
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

// After its impact a 32 x 32 hexagonal packing at e = 0.9 is a gas of beads flying and
// colliding until end_time. With nothing loaded, a search for the next meeting that would visit
// more pairs than its budget ends the flight where the neighbour lists have cleared it, not at
// one short window: until 0.6 s at tolerance 1e-5, 24 083 windows in 2.0 s (74 328 windows and
// 60 s when each such search ended in a short window; the same to the bit until 0.2 s).
TEST(PackingCost, AGasOfBeadsFliesAsFarAsItsListsHaveCleared) {
  const PackingCase gas = run_packing(
      lattice_scene("hexagonal", 32, 32, "[0, 16]", "[0.0, 1.0]",
                    R"("contact": {"model": "bi-stiffness", "exponent": 1.5, "restitution": 0.9},
         "method": "compliant",
         "compliant": {"tolerance": 1e-5, "geometry": "moving", "end_time": 0.6})"));
  const granular::MovingContactsStats& work = gas.run.moving;
  std::printf("windows %lld, body steps %lld\n", (long long)work.windows,
              (long long)work.member_steps);
  EXPECT_LT(work.windows, 30000);
  Eigen::Vector2d before = Eigen::Vector2d::Zero(), after = Eigen::Vector2d::Zero();
  double energy_before = 0.0, energy_after = 0.0;
  const Eigen::VectorXd& v = gas.run.impact.velocity_after;
  for (Eigen::Index k = 0; k < v.size(); ++k) {
    const double m = gas.model.mass(k);
    before(k % 2) += m * gas.model.velocity(k);
    after(k % 2) += m * v(k);
    energy_before += 0.5 * m * gas.model.velocity(k) * gas.model.velocity(k);
    energy_after += 0.5 * m * v(k) * v(k);
  }
  EXPECT_LT((after - before).norm(), 1e-12 * before.norm());
  EXPECT_LT(energy_after, energy_before);  // every collision at e = 0.9 takes some
}

}  // namespace
}  // namespace mimpact::testing
