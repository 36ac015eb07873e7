// "method": "auto" (issue 48): the cheaper model that meets the accuracy, decided and told. LZB
// where its frozen configuration is the beads' own (a chain) or within the accuracy of them
// (square and simple cubic packings struck along a row), the compliant moving geometry where it
// is not (hexagonal and FCC packings); either way the answer is within the accuracy of the beads
// as they move, integrated far tighter.
#include <gtest/gtest.h>

#include <string>

#include "mimpact/chains/chain_run.hpp"
#include "mimpact/chains/chain_scene.hpp"
#include "packing_runs.hpp"

namespace mimpact::testing {
namespace {

constexpr double kAccuracy = 1e-3;

// The worst body's distance (of the striker's 1 m/s) between two runs' velocities.
double worst_distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b, int dimension) {
  double worst = 0.0;
  for (Eigen::Index body = 0; body < a.size() / dimension; ++body)
    worst = std::max(
        worst,
        (a.segment(dimension * body, dimension) - b.segment(dimension * body, dimension)).norm());
  return worst;
}

// Runs the lattice with "method": "auto" at kAccuracy, checks the method it chose and that its
// answer is within the accuracy of the compliant moving geometry at tolerance 1e-8.
// A lattice of kSteel beads of 5 mm, `layers` deep (0: planar), struck as lattice_scene does.
std::string lattice(const std::string& type, int rows, int columns, int layers,
                    const std::string& target, const std::string& velocity,
                    const std::string& rest) {
  const std::string size = std::to_string(rows) + R"(, "columns": )" + std::to_string(columns) +
                           (layers > 0 ? R"(, "layers": )" + std::to_string(layers) : "");
  return "{" + kSteel + R"(, "lattice": {"type": ")" + type + R"(", "rows": )" + size +
         R"(, "radius": 0.005}, "strikers": [{"target": )" + target +
         R"(, "radius": 0.005, "velocity": )" + velocity + "}], " + rest + "}";
}

void expect_auto(const std::string& type, int rows, int columns, int layers,
                 const std::string& target, const std::string& velocity,
                 granular::Method expected) {
  const std::string rest =
      R"("contact": {"restitution": 0.9}, "compliant": {"end_time": 5e-4}, "accuracy": 1e-3)";
  const PackingCase chosen = run_packing(
      lattice(type, rows, columns, layers, target, velocity, rest + R"(, "method": "auto")"));
  const granular::SceneRun& run = chosen.run;
  EXPECT_EQ(run.method, expected) << type << ": " << run.why;
  EXPECT_NE(
      run.why.find(expected == granular::Method::lzb ? "LZB: the beads as they move"
                                                     : "the compliant contacts in the moving"),
      std::string::npos)
      << run.why;
  ASSERT_TRUE(run.configuration.has_value());
  EXPECT_EQ(run.configuration->holds(), expected == granular::Method::lzb);
  EXPECT_FALSE(run.configuration_fails());  // no warning: the method chosen is the right one
  EXPECT_TRUE(run.accuracy && run.accuracy->met);
  const std::string exact = R"("contact": {"restitution": 0.9}, "method": "compliant",
      "compliant": {"end_time": 5e-4, "tolerance": 1e-8})";
  const PackingCase moving =
      run_packing(lattice(type, rows, columns, layers, target, velocity, exact));
  const double worst = worst_distance(run.impact.velocity_after, moving.run.impact.velocity_after,
                                      chosen.model.dimension);
  std::printf("%s: %s; the answer is %.3g from the beads as they move\n", type.c_str(),
              run.why.c_str(), worst);
  EXPECT_LE(worst, kAccuracy) << type;
}

TEST(MethodAuto, LzbWhereItsConfigurationHolds) {
  expect_auto("square", 6, 6, 0, "[5, 2]", "[0, -1]", granular::Method::lzb);
  expect_auto("simple-cubic", 4, 4, 4, "[3, 1, 1]", "[0, 0, -1]", granular::Method::lzb);
}

TEST(MethodAuto, TheMovingGeometryWhereItDoesNot) {
  expect_auto("hexagonal", 8, 8, 0, "[7, 3]", "[0, -1]", granular::Method::compliant);
  expect_auto("fcc", 4, 4, 4, "[3, 1, 1]", "[0, 0, -1]", granular::Method::compliant);
}

TEST(MethodAuto, ChainsTakeLzbUnlessPressed) {
  const std::string chain = R"({"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
    "chain": {"segments": [{"count": 20, "radius": 0.010}]},
    "strikers": [{"side": "left", "radius": 0.010, "velocity": 1.0}], "wall": {},
    "contact": {"restitution": 0.9}, "method": "auto", "compliant": {"end_time": 1e-3})";
  for (const bool pressed : {false, true}) {
    const chains::ChainScene scene =
        chains::parse_chain_scene(chain + (pressed ? R"(, "precompression": 5})" : "}"), "chain");
    const chains::ChainModel model = chains::build_chain_model(scene);
    const granular::SceneRun run = chains::run_chain_scene(scene, model);
    EXPECT_EQ(run.method, pressed ? granular::Method::compliant : granular::Method::lzb);
    EXPECT_NE(run.why.find(pressed ? "precompressed" : "stay on its line"), std::string::npos)
        << run.why;
    EXPECT_TRUE(run.accuracy && run.accuracy->met && run.accuracy->asked == kAccuracy);
    EXPECT_EQ(chains::run_summary(model, run)["method_choice"], run.why);
  }
}

}  // namespace
}  // namespace mimpact::testing
