// Issue 12, item a: a square packing struck along a lattice row (or column) is, in that row,
// exactly the chain of its beads, and the other rows never move; a hexagonal packing of one row
// is a chain. Orthogonal contacts do not couple (H has no entry between a row's contact and a
// column's), so the row's impact is the chain's to round-off, by both LZB integrators.
#include <gtest/gtest.h>

#include <cmath>

#include "mimpact/chains/chain_impact.hpp"
#include "mimpact/chains/chain_run.hpp"
#include "packing_runs.hpp"

namespace mimpact::testing {
namespace {

struct Method {
  const char* name;
  std::string impact;  // the scene's "impact"
};

const Method kMethods[] = {
    {"impulse steps", R"("impact": {"delta_p": 4e-6})"},
    {"adaptive", R"("impact": {"integrator": "adaptive", "tolerance": 1e-9})"}};

// C beads in a chain struck from the left at 1 m/s by an equal bead.
granular::ImpactOutcome chain_of(int beads, const std::string& impact) {
  const chains::ChainScene scene = chains::parse_chain_scene(
      "{" + kSteel + R"(, "chain": {"segments": [{"count": )" + std::to_string(beads) +
          R"(, "radius": 0.005}]}, "strikers": [{"side": "left", "radius": 0.005, "velocity": 1.0}], )" +
          impact + "}",
      "chain");
  const chains::ChainModel model = chains::build_chain_model(scene);
  plugins::LzbImpactOptions options = scene.impact;
  return chains::simulate_chain_impact(model, options);
}

// The packing's contact between bodies a and b.
Eigen::Index contact_between(const packings::PackingModel& model, Eigen::Index a, Eigen::Index b) {
  for (std::size_t c = 0; c < model.contacts.size(); ++c) {
    const packings::PackingContact& contact = model.contacts[c];
    if ((contact.first == a && contact.second == b) || (contact.first == b && contact.second == a))
      return Eigen::Index(c);
  }
  ADD_FAILURE() << "no contact between " << a << " and " << b;
  return 0;
}

// beads[k] of the packing is bead k of the chain; `axis` the line's direction (0 x, 1 y, 2 z).
void expect_chain(const PackingCase& packing, const std::vector<Eigen::Index>& beads, int axis,
                  const granular::ImpactOutcome& chain) {
  const packings::PackingModel& model = packing.model;
  const int d = model.dimension;
  const Eigen::VectorXd& v = packing.run.impact.velocity_after;
  const Eigen::Index striker = model.body_count() - 1;
  // the body's velocity along the line, and across it (exactly 0)
  auto along = [&](Eigen::Index b) { return v(d * b + axis); };
  auto across = [&](Eigen::Index b) {
    Eigen::VectorXd w = model.of(v, b);
    w(axis) = 0.0;
    return w.norm();
  };
  EXPECT_NEAR(along(striker), chain.velocity_after(0), 1e-12);
  EXPECT_EQ(across(striker), 0.0);
  for (std::size_t k = 0; k < beads.size(); ++k) {
    EXPECT_NEAR(along(beads[k]), chain.velocity_after(Eigen::Index(k) + 1), 1e-12) << k;
    EXPECT_EQ(across(beads[k]), 0.0) << k;
  }
  // every other bead is untouched, exactly
  double others = 0.0;
  for (Eigen::Index b = 0; b < model.bead_count; ++b)
    if (std::find(beads.begin(), beads.end(), b) == beads.end())
      others = std::max(others, model.of(v, b).norm());
  EXPECT_EQ(others, 0.0);
  const Eigen::VectorXd& peak = packing.run.impact.result.max_force;
  const double largest = chain.result.max_force.maxCoeff();
  EXPECT_NEAR(peak(contact_between(model, beads[0], striker)), chain.result.max_force(0),
              1e-12 * largest);
  for (std::size_t k = 0; k + 1 < beads.size(); ++k)
    EXPECT_NEAR(peak(contact_between(model, beads[k], beads[k + 1])),
                chain.result.max_force(Eigen::Index(k) + 1), 1e-12 * largest)
        << k;
}

TEST(PackingReduction, SquarePackingStruckAlongARowIsTheChainOfThatRow) {
  constexpr int kRows = 5, kColumns = 8, kRow = 2;
  for (const Method& method : kMethods) {
    SCOPED_TRACE(method.name);
    const PackingCase packing = run_packing(
        lattice_scene("square", kRows, kColumns, "[2, 0]", "[1.0, 0.0]", method.impact));
    std::vector<Eigen::Index> row;
    for (int c = 0; c < kColumns; ++c) row.push_back(kRow * kColumns + c);
    expect_chain(packing, row, 0, chain_of(kColumns, method.impact));
  }
}

TEST(PackingReduction, SquarePackingStruckAlongAColumnIsTheChainOfThatColumn) {
  constexpr int kRows = 7, kColumns = 4, kColumn = 1;
  for (const Method& method : kMethods) {
    SCOPED_TRACE(method.name);
    const PackingCase packing = run_packing(
        lattice_scene("square", kRows, kColumns, "[0, 1]", "[0.0, 1.0]", method.impact));
    std::vector<Eigen::Index> column;
    for (int r = 0; r < kRows; ++r) column.push_back(r * kColumns + kColumn);
    expect_chain(packing, column, 1, chain_of(kRows, method.impact));
  }
}

TEST(PackingReduction, HexagonalPackingOfOneRowIsAChain) {
  constexpr int kColumns = 10;
  for (const Method& method : kMethods) {
    SCOPED_TRACE(method.name);
    const PackingCase packing =
        run_packing(lattice_scene("hexagonal", 1, kColumns, "[0, 0]", "[1.0, 0.0]", method.impact));
    std::vector<Eigen::Index> row(kColumns);
    std::iota(row.begin(), row.end(), Eigen::Index(0));
    expect_chain(packing, row, 0, chain_of(kColumns, method.impact));
  }
}

// Issue 24, item d: a simple cubic packing struck along a row (x) or a column of its layers
// (z) is the chain of that line, and every other bead stays at rest.
TEST(PackingReduction, SimpleCubicPackingStruckAlongALineIsTheChainOfThatLine) {
  constexpr int kLayers = 4, kRows = 3, kColumns = 5;
  const std::string lattice = R"("lattice": {"type": "simple-cubic", "layers": 4, "rows": 3,
                                  "columns": 5, "radius": 0.005})";
  for (const Method& method : kMethods) {
    SCOPED_TRACE(method.name);
    const PackingCase along_row =
        run_packing("{" + kSteel + ", " + lattice + R"(, "strikers": [{"target": [2, 1, 0],
            "radius": 0.005, "velocity": [1.0, 0.0, 0.0]}], )" +
                    method.impact + "}");
    std::vector<Eigen::Index> row;
    for (int c = 0; c < kColumns; ++c) row.push_back((2 * kRows + 1) * kColumns + c);
    expect_chain(along_row, row, 0, chain_of(kColumns, method.impact));
    const PackingCase across_layers =
        run_packing("{" + kSteel + ", " + lattice + R"(, "strikers": [{"target": [0, 2, 3],
            "radius": 0.005, "velocity": [0.0, 0.0, 1.0]}], )" +
                    method.impact + "}");
    std::vector<Eigen::Index> column;
    for (int l = 0; l < kLayers; ++l) column.push_back((l * kRows + 2) * kColumns + 3);
    expect_chain(across_layers, column, 2, chain_of(kLayers, method.impact));
  }
}

// Issue 24, item a: in the moving geometry the beads of a line are still a chain, whose gaps
// are linear: the compliant contacts of a hexagonal packing of one row and of a simple cubic
// one struck along a row (granular::MovingContacts) equal those of the chain (the frozen
// geometry's integrator), each run at tolerance 1e-14, the finest a scene allows (measured:
// 6.3e-13 m/s, the two integrators' own errors; 8.2e-13 to 1.3e-12 as the windows changed).
TEST(PackingReduction, ALineInTheMovingGeometryIsTheChain) {
  const std::string compliant = R"("method": "compliant", "compliant": {"tolerance": 1e-14})";
  const chains::ChainScene scene = chains::parse_chain_scene(
      "{" + kSteel + R"(, "chain": {"segments": [{"count": 10, "radius": 0.005}]},
          "strikers": [{"side": "left", "radius": 0.005, "velocity": 1.0}], )" +
          compliant + "}",
      "chain");
  const granular::SceneRun chain = chains::run_chain_scene(scene, chains::build_chain_model(scene));
  const PackingCase line =
      run_packing(lattice_scene("hexagonal", 1, 10, "[0, 0]", "[1.0, 0.0]", compliant));
  const PackingCase cubic = run_packing("{" + kSteel + R"(, "lattice": {"type": "simple-cubic",
      "layers": 2, "rows": 2, "columns": 10, "radius": 0.005}, "strikers": [{"target": [1, 0, 0],
      "radius": 0.005, "velocity": [1.0, 0.0, 0.0]}], )" +
                                        compliant + "}");
  for (const PackingCase* packing : {&line, &cubic}) {
    const Eigen::VectorXd& v = packing->run.impact.velocity_after;
    const int d = packing->model.dimension;
    const Eigen::Index first = packing == &line ? 0 : 2 * 10,
                       striker = packing->model.body_count() - 1;
    double largest = std::abs(v(d * striker) - chain.impact.velocity_after(0));
    for (Eigen::Index k = 0; k < 10; ++k)
      largest =
          std::max(largest, std::abs(v(d * (first + k)) - chain.impact.velocity_after(k + 1)));
    std::printf("%dd line against the chain: %.3e m/s\n", d, largest);
    EXPECT_LT(largest, 1e-12);
  }
}

// The same for inelastic contacts (bi-stiffness, e = 0.5 and 0.9), whose law turns at every
// contact's largest overlap: the chain's integrator locates each turn and restarts there, the
// moving geometry finds it within its step and amends the step (docs/design/moving_geometry.md).
// Measured: 5.2e-13 m/s at e = 0.5, 1.5e-12 at e = 0.9, where the moving geometry that located
// its turns too (before 2026-11-28) was 1.2e-12 from the chain: both integrators' floor at
// tolerance 1e-14, bounded at 2e-12.
TEST(PackingReduction, AnInelasticLineInTheMovingGeometryIsTheChain) {
  for (const double restitution : {0.5, 0.9}) {
    const std::string physics =
        R"("contact": {"model": "bi-stiffness", "exponent": 1.5, "restitution": )" +
        std::to_string(restitution) +
        R"(}, "method": "compliant", "compliant": {"tolerance": 1e-14})";
    const chains::ChainScene scene = chains::parse_chain_scene(
        "{" + kSteel + R"(, "chain": {"segments": [{"count": 10, "radius": 0.005}]},
            "strikers": [{"side": "left", "radius": 0.005, "velocity": 1.0}], )" +
            physics + "}",
        "chain");
    const granular::SceneRun chain =
        chains::run_chain_scene(scene, chains::build_chain_model(scene));
    const PackingCase line =
        run_packing(lattice_scene("hexagonal", 1, 10, "[0, 0]", "[1.0, 0.0]", physics));
    const Eigen::VectorXd& v = line.run.impact.velocity_after;
    const Eigen::Index striker = line.model.body_count() - 1;
    double largest = std::abs(v(2 * striker) - chain.impact.velocity_after(0));
    for (Eigen::Index k = 0; k < 10; ++k)
      largest = std::max(largest, std::abs(v(2 * k) - chain.impact.velocity_after(k + 1)));
    std::printf("e = %.1f: the line against the chain: %.3e m/s\n", restitution, largest);
    EXPECT_LT(largest, 2e-12) << "e = " << restitution;
  }
}

}  // namespace
}  // namespace mimpact::testing

namespace mimpact::testing {
namespace {

// Strikers arriving at different times: successive impacts, located by the event-driven scheme, as
// in the chain of the struck row (item 2).
TEST(PackingReduction, StaggeredStrikersMakeTheChainsImpacts) {
  const std::string impact = R"("impact": {"integrator": "adaptive", "tolerance": 1e-9})";
  const PackingCase packing =
      run_packing("{" + kSteel +
                  R"(, "lattice": {"type": "square", "rows": 3, "columns": 6, "radius": 0.005},
           "strikers": [{"target": [1, 0], "radius": 0.005, "velocity": [1.0, 0.0], "gap": 1e-4},
                        {"target": [1, 5], "radius": 0.005, "velocity": [-1.5, 0.0], "gap": 6e-4}], )" +
                  impact + "}");
  const chains::ChainScene scene =
      chains::parse_chain_scene("{" + kSteel +
                                    R"(, "chain": {"segments": [{"count": 6, "radius": 0.005}]},
               "strikers": [{"side": "left", "radius": 0.005, "velocity": 1.0, "gap": 1e-4},
                            {"side": "right", "radius": 0.005, "velocity": 1.5, "gap": 6e-4}], )" +
                                    impact + "}",
                                "chain");
  const chains::ChainModel model = chains::build_chain_model(scene);
  const granular::ImpactOutcome chain = chains::simulate_chain_impact(model, scene.impact);
  // the left striker's impact sends the last bead at the right striker: they meet before the
  // striker would reach a bead at rest, and the beads meet again twice (4 impacts)
  ASSERT_GE(chain.impact_times.size(), 2u);
  ASSERT_EQ(packing.run.impact.impact_times.size(), chain.impact_times.size());
  const Eigen::VectorXd& v = packing.run.impact.velocity_after;
  const Eigen::Index left = packing.model.bead_count, right = left + 1;
  EXPECT_NEAR(v(2 * left), chain.velocity_after(0), 1e-12);
  EXPECT_NEAR(v(2 * right), chain.velocity_after(7), 1e-12);
  for (Eigen::Index k = 0; k < 6; ++k)
    EXPECT_NEAR(v(2 * (6 + k)), chain.velocity_after(k + 1), 1e-12) << k;
  for (std::size_t k = 0; k < chain.impact_times.size(); ++k)
    EXPECT_NEAR(packing.run.impact.impact_times[k], chain.impact_times[k], 1e-15) << k;
}

}  // namespace
}  // namespace mimpact::testing
