#pragma once

// Planar packing scenes written in the tests, and their runs.

#include <string>

#include "mimpact/packings/packing_run.hpp"

namespace mimpact::testing {

// C1's steel (docs/experiments.md), beads of 5 mm.
inline const std::string kSteel =
    R"("material": {"density": 7780, "young": 203e9, "poisson": 0.3})";

// A lattice struck by one bead of its radius at `target` with `velocity`; `rest` adds keys.
inline std::string lattice_scene(const std::string& type, int rows, int columns,
                                 const std::string& target, const std::string& velocity,
                                 const std::string& rest) {
  return "{" + kSteel + R"(, "lattice": {"type": ")" + type + R"(", "rows": )" +
         std::to_string(rows) + R"(, "columns": )" + std::to_string(columns) +
         R"(, "radius": 0.005}, "strikers": [{"target": )" + target +
         R"(, "radius": 0.005, "velocity": )" + velocity + "}]" +
         (rest.empty() ? "" : ", " + rest) + "}";
}

struct PackingCase {
  packings::PackingScene scene;
  packings::PackingModel model;
  granular::SceneRun run;
};

// `directory`: where its bead lists are (the source tree by default)
inline PackingCase run_packing(const std::string& text,
                               const std::string& directory = MIMPACT_SOURCE_DIR) {
  PackingCase result;
  result.scene = packings::parse_packing_scene(text, "test scene", directory);
  result.model = packings::build_packing_model(result.scene);
  result.run = packings::run_packing_scene(result.scene, result.model);
  return result;
}

}  // namespace mimpact::testing
