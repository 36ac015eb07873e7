// Planar packing scenes: lattice geometry and contacts found by the neighbour search, and one
// clear error for each kind of bad input (issue 12, item 1).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "packing_runs.hpp"

namespace mimpact::testing {
namespace {

packings::PackingModel model_of(const std::string& text) {
  return packings::build_packing_model(
      packings::parse_packing_scene(text, "scene", std::filesystem::temp_directory_path()));
}

// The message of the InvalidInput that `text` raises, or "" when it raises none.
std::string error_of(const std::string& text) {
  try {
    model_of(text);
  } catch (const InvalidInput& error) {
    return error.what();
  }
  return "";
}

TEST(PackingScene, LatticesHaveTheirNeighbourCounts) {
  // R x C square: R (C - 1) + C (R - 1) contacts; hexagonal adds one diagonal pair per bead
  // between rows: R (C - 1) + (R - 1) (2 C - 1); plus the striker's
  const packings::PackingModel square =
      model_of(lattice_scene("square", 4, 6, "[0, 2]", "[0, 1]", ""));
  EXPECT_EQ(square.contact_count(), 4 * 5 + 6 * 3 + 1);
  const packings::PackingModel hexagonal =
      model_of(lattice_scene("hexagonal", 4, 6, "[0, 2]", "[0, 1]", ""));
  EXPECT_EQ(hexagonal.contact_count(), 4 * 5 + 3 * 11 + 1);
  // every bead-bead contact joins beads 2a apart, along a unit normal
  for (const packings::PackingContact& contact : hexagonal.contacts) {
    if (contact.second >= hexagonal.bead_count) continue;
    const Eigen::Vector2d between =
        (hexagonal.position.row(contact.second) - hexagonal.position.row(contact.first))
            .transpose();
    EXPECT_NEAR(between.norm(), 0.01, 1e-15);
    EXPECT_NEAR(contact.normal.dot(between), 0.01, 1e-15);
  }
}

TEST(PackingScene, WallsTouchTheOutermostBeads) {
  const packings::PackingModel model = model_of(
      lattice_scene("hexagonal", 3, 4, "[2, 1]", "[0, -1]", R"("walls": [{"side": "bottom"}])"));
  int wall_contacts = 0;
  for (const packings::PackingContact& contact : model.contacts)
    if (contact.wall == 0) {
      ++wall_contacts;
      EXPECT_LT(contact.first, 4);  // row 0 only
    }
  EXPECT_EQ(wall_contacts, 4);
}

TEST(PackingScene, BeadListsAreReadFromCsv) {
  const auto file = std::filesystem::temp_directory_path() / "mimpact_three_beads.csv";
  std::ofstream(file) << "x,y,radius\n0,0,0.005\n0.01,0,0.005\n0.005,0.0086602540378,0.005\n";
  const packings::PackingModel model = model_of(
      "{" + kSteel +
      R"(, "beads": {"file": "mimpact_three_beads.csv"}, "strikers": [{"target": [2], "radius": 0.005, "velocity": [0, -1]}]})");
  EXPECT_EQ(model.bead_count, 3);
  EXPECT_EQ(model.contact_count(), 3 + 1);  // a triangle, and the striker on top
}

TEST(PackingScene, BadInputGetsOneClearError) {
  const auto file = std::filesystem::temp_directory_path() / "mimpact_overlap.csv";
  std::ofstream(file) << "x,y,radius\n0,0,0.005\n0.009,0,0.005\n";
  const auto empty = std::filesystem::temp_directory_path() / "mimpact_empty.csv";
  std::ofstream(empty) << "x,y,radius\n";
  const std::string striker =
      R"("strikers": [{"target": [0], "radius": 0.005, "velocity": [1, 0]}])";
  EXPECT_NE(
      error_of("{" + kSteel + R"(, "beads": {"file": "mimpact_overlap.csv"}, )" + striker + "}")
          .find("mimpact_overlap.csv lines 2 and 3: bead 0 and bead 1 overlap by 0.001"),
      std::string::npos);
  EXPECT_NE(error_of("{" + kSteel + R"(, "beads": {"file": "mimpact_empty.csv"}, )" + striker + "}")
                .find("the bead list is empty"),
            std::string::npos);
  EXPECT_NE(error_of(lattice_scene("square", 2, 2, "[0, 0]", "[1, 0]",
                                   R"("walls": [{"point": [0.002, 0], "normal": [1, 0]}])"))
                .find("m into walls[0]"),
            std::string::npos);
  EXPECT_NE(error_of(lattice_scene("square", 2, 2, "[0, 5]", "[1, 0]", ""))
                .find("strikers[0].target[1] = 5 is invalid; allowed: a column in [0, 2): the "
                      "striker is aimed at nothing"),
            std::string::npos);
  EXPECT_NE(error_of(lattice_scene("square", 2, 2, "[0, 0]", "[0, 0]", ""))
                .find("strikers[0].velocity = [0, 0] is invalid"),
            std::string::npos);
  EXPECT_NE(error_of(lattice_scene("square", 0, 2, "[0, 0]", "[1, 0]", ""))
                .find("lattice.rows = 0 is invalid"),
            std::string::npos);
  // aimed at a bead in the middle of the packing: it would land on the target's neighbour
  EXPECT_NE(error_of(lattice_scene("square", 3, 3, "[1, 1]", "[1, 0]", ""))
                .find("strikers[0] would overlap bead 3 (row 1, column 0)"),
            std::string::npos);
}

TEST(PackingScene, RecordedContactsOutOfRangeAreRefused) {
  const packings::PackingScene scene = packings::parse_packing_scene(
      lattice_scene("square", 2, 2, "[0, 0]", "[1, 0]",
                    R"("impact": {"delta_p": 1e-5}, "record": {"contacts": [99]})"),
      "scene");
  const packings::PackingModel model = packings::build_packing_model(scene);
  try {
    packings::run_packing_scene(scene, model);
    FAIL() << "no error";
  } catch (const InvalidInput& error) {
    EXPECT_NE(std::string(error.what()).find("record.contacts[0] = 99 is invalid"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace mimpact::testing
