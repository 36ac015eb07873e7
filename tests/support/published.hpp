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

// The value in `column` of the one row of set `name` whose columns equal `match`, as in
// published_value("colliding_waves", "simulated", {{"beads", 25}, {"quantity", "..."}}).
inline double published_value(const std::string& name, const std::string& column,
                              const nlohmann::json& match) {
  const nlohmann::json& set = published(name);
  const nlohmann::json& columns = set.at("columns");
  auto index = [&](const std::string& key) -> std::size_t {
    for (std::size_t k = 0; k < columns.size(); ++k)
      if (columns[k] == key) return k;
    throw std::runtime_error(name + ": no column " + key);
  };
  const nlohmann::json* found = nullptr;
  for (const auto& row : set.at("rows")) {
    bool matches = true;
    for (const auto& [key, value] : match.items()) matches = matches && row[index(key)] == value;
    if (!matches) continue;
    if (found) throw std::runtime_error(name + ": more than one row matches " + match.dump());
    found = &row;
  }
  if (!found) throw std::runtime_error(name + ": no row matches " + match.dump());
  return (*found)[index(column)].get<double>();
}

// A row of Nguyen & Brogliato's tables 2-4: the step count they publish (one more than the steps
// taken) at delta_p (N s), for chain "C1", "C2" or "C3".
inline std::int64_t published_steps(const std::string& chain, double delta_p) {
  for (const auto& row : published("convergence").at(chain))
    if (row[0].get<double>() == delta_p) return row[1].get<std::int64_t>();
  throw std::runtime_error(chain + ": no published row at delta_p = " + std::to_string(delta_p));
}

}  // namespace mimpact::testing
