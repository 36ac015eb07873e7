#pragma once

// Planar packing scenes written in the tests, and their runs.

#include <Eigen/Dense>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

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

// The planar velocities (m/s, a row per body) of a LAMMPS run vendored in tests/data/lammps/
// (its README says how each was made).
inline Eigen::MatrixX2d lammps_velocities(const std::string& name) {
  std::ifstream file(std::string(MIMPACT_SOURCE_DIR) + "/tests/data/lammps/" + name);
  std::string line;
  std::getline(file, line);  // vx,vy,vz
  std::vector<double> values;
  double vx, vy;
  while (std::getline(file, line)) {
    if (std::sscanf(line.c_str(), "%lf,%lf", &vx, &vy) != 2)
      throw std::runtime_error(name + ": not vx,vy,vz: " + line);
    values.insert(values.end(), {vx, vy});
  }
  return Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>(
      values.data(), Eigen::Index(values.size() / 2), 2);
}

}  // namespace mimpact::testing
