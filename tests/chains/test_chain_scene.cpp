// Scene files: what a valid scene builds, and the one-line error of every invalid one.
#include "mimpact/chains/chain_scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mimpact/chains/chain_model.hpp"
#include "mimpact/common/error.hpp"

namespace mimpact::chains {
namespace {

constexpr const char* kValid = R"({
  // comments are allowed
  "material": {"density": 7780, "young": 203e9, "poisson": 0.3},
  "chain": {"segments": [{"count": 3, "radius": 0.010, "taper": 0.1},
                         {"count": 2, "radius": 0.005,
                          "material": {"density": 2700, "young": 70e9, "poisson": 0.33}}]},
  "strikers": [{"side": "left", "radius": 0.004, "velocity": 0.5}],
  "contact": {"model": "mono-stiffness", "exponent": 1.5, "restitution": 0.9},
  "impact": {"delta_p": 1e-6}
})";

TEST(ChainScene, ValidSceneBuildsTheChainItDescribes) {
  const ChainScene scene = parse_chain_scene(kValid, "valid.json");
  const ChainModel model = build_chain_model(scene);
  ASSERT_EQ(model.body_count(), 6);  // striker + 3 + 2
  ASSERT_EQ(model.contact_count(), 5);
  const double radii[] = {0.004, 0.010, 0.009, 0.0081, 0.005, 0.005};
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(model.radius(i), radii[i], 1e-15);
  const double steel = 4.0 / 3.0 * std::numbers::pi * 7780;
  EXPECT_NEAR(model.mass(1), steel * 1e-6, 1e-15);
  EXPECT_NEAR(model.mass(5), 4.0 / 3.0 * std::numbers::pi * 2700 * 1.25e-7, 1e-15);
  EXPECT_EQ(model.velocity(0), 0.5);
  EXPECT_EQ(model.u_minus(0), -0.5);  // the striker approaches the first bead
  for (int j = 1; j < 5; ++j) EXPECT_EQ(model.u_minus(j), 0.0);

  // Hertz between steel beads 1 and 2: K = 4/3 sqrt(R*) E*
  const double r_star = 0.010 * 0.009 / 0.019;
  const double e_star = 203e9 / (2.0 * (1.0 - 0.09));
  EXPECT_NEAR(model.laws[1].stiffness, 4.0 / 3.0 * std::sqrt(r_star) * e_star, 1e-3);
  EXPECT_EQ(model.laws[1].restitution, 0.9);
  EXPECT_EQ(model.laws[1].model, numerics::ComplianceModel::mono_stiffness);

  // H = W^T M^-1 W: tridiagonal with 1/m_i + 1/m_{i+1} and -1/m_{i+1}
  const Eigen::MatrixXd H = model.H;
  EXPECT_NEAR(H(2, 2), 1.0 / model.mass(2) + 1.0 / model.mass(3), 1e-9);
  EXPECT_NEAR(H(2, 3), -1.0 / model.mass(3), 1e-9);
  EXPECT_EQ(H(0, 2), 0.0);
  EXPECT_EQ(*scene.impact.delta_p, 1e-6);
}

// The error of a bad scene names the field and what is allowed, in one line.
std::string error_of(const std::string& text) {
  try {
    parse_chain_scene(text, "bad.json");
  } catch (const InvalidInput& error) {
    const std::string what = error.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_EQ(what.rfind("bad.json:", 0), 0u) << what;
    return what;
  }
  ADD_FAILURE() << "no error for " << text;
  return "";
}

std::string with(const std::string& from, const std::string& to) {
  std::string text = kValid;
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

// A chain given bead by bead ("beads": a radius and a material each) is the chain its segments
// describe: the same bodies, masses and laws; a dimer chain (alternating radii, one bead of
// another material) needs no segment per bead.
TEST(ChainScene, BeadByBeadIsTheChainOfTheSegments) {
  const std::string aluminium = R"({"density": 2700, "young": 70e9, "poisson": 0.33})";
  const ChainModel segments = build_chain_model(parse_chain_scene(kValid, "segments.json"));
  const ChainModel beads = build_chain_model(parse_chain_scene(
      with(R"("chain": {"segments": [{"count": 3, "radius": 0.010, "taper": 0.1},
                         {"count": 2, "radius": 0.005,
                          "material": {"density": 2700, "young": 70e9, "poisson": 0.33}}]})",
           R"("chain": {"beads": [{"radius": 0.010}, {"radius": 0.009}, {"radius": 0.0081},
                                   {"radius": 0.005, "material": )" +
               aluminium + R"(}, {"radius": 0.005, "material": )" + aluminium + "}]}"),
      "beads.json"));
  ASSERT_EQ(beads.body_count(), segments.body_count());
  for (Eigen::Index b = 0; b < beads.body_count(); ++b) {
    EXPECT_NEAR(beads.radius(b), segments.radius(b), 1e-15 * segments.radius(b)) << b;
    EXPECT_NEAR(beads.mass(b), segments.mass(b), 1e-14 * segments.mass(b)) << b;
  }
  for (std::size_t j = 0; j < beads.laws.size(); ++j)
    EXPECT_NEAR(beads.laws[j].stiffness, segments.laws[j].stiffness,
                1e-14 * segments.laws[j].stiffness)
        << j;
  // the bead list's own errors name the bead
  EXPECT_NE(error_of(with(R"("chain": {"segments")",
                          R"("chain": {"beads": [{"radius": 0.01}], "segments")"))
                .find("both \"segments\" and \"beads\""),
            std::string::npos);
  auto bead_error = [&](const std::string& chain) {
    return error_of(R"({"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
      "chain": )" + chain +
                    R"(, "strikers": [{"radius": 0.01, "velocity": 1}]})");
  };
  EXPECT_NE(bead_error(R"({"beads": [{"radius": 0.01}, {"radius": -0.01}]})")
                .find("chain.beads[1].radius = -0.01 is invalid"),
            std::string::npos);
  EXPECT_NE(bead_error(R"({"beads": []})").find("chain needs its beads"), std::string::npos);
  EXPECT_NE(bead_error(R"({"beads": [{"diameter": 0.01}]})").find("unknown key \"diameter\""),
            std::string::npos);
}

TEST(ChainScene, EveryBadFieldIsNamed) {
  auto has = [](const std::string& message, const std::string& part) {
    return message.find(part) != std::string::npos;
  };
  EXPECT_TRUE(has(error_of("{\"chain\": "), "malformed JSON"));
  EXPECT_TRUE(has(error_of(with("\"impact\"", "\"impacts\"")), "unknown key \"impacts\""));
  EXPECT_TRUE(has(error_of(with("\"taper\": 0.1", "\"tapper\": 0.1")),
                  "unknown key \"tapper\" in chain.segments[0]"));
  EXPECT_TRUE(has(error_of(with("\"radius\": 0.010,", "\"radius\": -0.010,")),
                  "chain.segments[0].radius = -0.01 is invalid"));
  EXPECT_TRUE(has(error_of(with("\"restitution\": 0.9", "\"restitution\": 1.2")),
                  "contact.restitution = 1.2 is invalid; allowed: 0 <= e <= 1"));
  EXPECT_TRUE(has(error_of(with("\"taper\": 0.1", "\"taper\": 1")), "taper = 1 is invalid"));
  EXPECT_TRUE(has(error_of(with("\"count\": 3", "\"count\": 0")),
                  "chain.segments[0].count = 0 is invalid"));
  EXPECT_TRUE(has(error_of(with("\"count\": 3", "\"count\": 2.5")), "an integer >= 1"));
  EXPECT_TRUE(has(error_of(with("\"velocity\": 0.5", "\"velocity\": -0.5")),
                  "strikers[0].velocity = -0.5 is invalid; allowed: >= 1e-100 (m/s, towards the "
                  "chain"));
  EXPECT_TRUE(has(error_of(with("\"side\": \"left\"", "\"side\": \"up\"")),
                  "strikers[0].side = \"up\" is invalid; allowed: \"left\", \"right\""));
  EXPECT_TRUE(has(
      error_of(with("\"strikers\": [{\"side\": \"left\", \"radius\": 0.004, \"velocity\": 0.5}]",
                    "\"strikers\": [{\"radius\": 0.004, \"velocity\": 0.5}, "
                    "{\"side\": \"left\", \"radius\": 0.004, \"velocity\": 0.5}]")),
      "both on the same side"));
  EXPECT_TRUE(has(
      error_of(with("\"side\": \"left\"", "\"side\": \"right\"").replace(0, 1, "{\"wall\": {},")),
      "a right striker and a wall"));
  EXPECT_TRUE(
      has(error_of(with("\"impact\": {\"delta_p\": 1e-6}",
                        "\"impact\": {\"delta_p\": 1e-6}, \"record\": {\"contacts\": [5]}")),
          "record.contacts[0] = 5 is invalid; allowed: a contact index in [0, 5)"));
  EXPECT_TRUE(has(error_of(with("\"impact\": {\"delta_p\": 1e-6}",
                                "\"impact\": {\"delta_p\": 1e-6}, \"record\": {\"every\": 0}")),
                  "record.every = 0 is invalid"));
  EXPECT_TRUE(has(error_of(with("\"model\": \"mono-stiffness\"", "\"model\": \"soft\"")),
                  "contact.model = \"soft\" is invalid"));
  EXPECT_TRUE(has(error_of(with("\"exponent\": 1.5", "\"exponent\": 1.0")),
                  "missing field contact.stiffness"));
  EXPECT_TRUE(has(error_of(with("\"radius\": 0.004,", "")), "missing field strikers[0].radius"));
  EXPECT_TRUE(has(error_of(with("\"density\": 7780", "\"density\": \"heavy\"")),
                  "material.density = \"heavy\" (a string) is invalid; allowed: a number"));
  EXPECT_TRUE(has(error_of(with("\"delta_p\": 1e-6", "\"delta_p\": 0")), "impact.delta_p = 0"));
  EXPECT_TRUE(
      has(error_of(with("\"poisson\": 0.3", "\"poisson\": 0.5")), "material.poisson = 0.5"));
}

TEST(ChainScene, RightStrikerAndWallBuildTheirBodiesAndContacts) {
  // a right striker is the last body, moving left; its gap sets its position
  ChainScene scene = parse_chain_scene(
      with("\"strikers\": [{\"side\": \"left\", \"radius\": 0.004, \"velocity\": 0.5}]",
           "\"strikers\": [{\"side\": \"left\", \"radius\": 0.004, \"velocity\": 0.5},"
           " {\"side\": \"right\", \"radius\": 0.003, \"velocity\": 0.25, \"gap\": 0.001}]"),
      "two.json");
  ChainModel model = build_chain_model(scene);
  ASSERT_EQ(model.body_count(), 7);
  ASSERT_EQ(model.contact_count(), 6);
  EXPECT_EQ(model.velocity(6), -0.25);
  EXPECT_NEAR(model.position(6) - model.position(5), 0.005 + 0.003 + 0.001, 1e-15);
  EXPECT_EQ(model.u_minus(5), -0.25);
  EXPECT_EQ(model.striker_arrivals, (std::vector<double>{0.0, 0.001 / 0.25}));

  // a wall after the last bead: one more contact, last, against an immovable body
  scene = parse_chain_scene(std::string(kValid).replace(1, 0, "\"wall\": {},"), "wall.json");
  model = build_chain_model(scene);
  ASSERT_EQ(model.contact_count(), 6);
  EXPECT_TRUE(model.has_wall);
  const Eigen::MatrixXd H = model.H;
  EXPECT_NEAR(H(5, 5), 1.0 / model.mass(5), 1e-9);  // the wall does not move
  EXPECT_NEAR(H(4, 5), -1.0 / model.mass(5), 1e-9);
  const granular::Material steel{7780, 203e9, 0.3}, aluminium{2700, 70e9, 0.33};
  EXPECT_NEAR(model.laws[5].stiffness, hertz_stiffness_wall(0.005, aluminium, steel), 1e-3);
}

TEST(ChainScene, MaterialFallsBackToTheTopLevelOne) {
  const std::string text =
      with("\"material\": {\"density\": 7780, \"young\": 203e9, \"poisson\": 0.3},", "");
  const std::string message = error_of(text);
  EXPECT_NE(message.find("missing field chain.segments[0].material"), std::string::npos) << message;
}

}  // namespace
}  // namespace mimpact::chains
