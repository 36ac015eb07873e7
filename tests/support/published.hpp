#pragma once

// The papers' numbers the tests compare with, read from the one file that holds them with their
// sources (examples/scenes/paper/published.json), as scripts/reproduce_paper.py reads them.

#include <cstdint>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

namespace mimpact::testing {

// The set `name` of published.json ("convergence", ...).
inline const nlohmann::json& published(const std::string& name) {
  static const nlohmann::json all = [] {
    const std::string path =
        std::string(MIMPACT_SOURCE_DIR) + "/examples/scenes/paper/published.json";
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path);
    return nlohmann::json::parse(in);
  }();
  return all.at(name);
}

// A row of Nguyen & Brogliato's tables 2-4: the step count they publish (one more than the steps
// taken) at delta_p (N s), for chain "C1", "C2" or "C3".
inline std::int64_t published_steps(const std::string& chain, double delta_p) {
  for (const auto& row : published("convergence").at(chain))
    if (row[0].get<double>() == delta_p) return row[1].get<std::int64_t>();
  throw std::runtime_error(chain + ": no published row at delta_p = " + std::to_string(delta_p));
}

}  // namespace mimpact::testing
