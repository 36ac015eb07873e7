#include "packing_beads.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>

#include "mimpact/common/error.hpp"
#include "mimpact/kernel/json_document.hpp"

namespace mimpact::packings {

std::vector<Body> lattice_beads(const LatticeSpec& lattice) {
  std::vector<Body> beads;
  const double a = lattice.radius;
  const int d = lattice_dimension(lattice.type);
  const bool close_packed =
      lattice.type != LatticeType::square && lattice.type != LatticeType::simple_cubic;
  const double row_pitch = close_packed ? std::sqrt(3.0) * a : 2.0 * a;
  const double layer_pitch = close_packed ? 2.0 * std::sqrt(2.0 / 3.0) * a : 2.0 * a;
  // the layers' stacking: FCC shifts each layer by (a, a / sqrt(3)) from the one below, three
  // positions in turn; HCP alternates two
  const int positions = lattice.type == LatticeType::fcc   ? 3
                        : lattice.type == LatticeType::hcp ? 2
                                                           : 1;
  const int layers = std::max(lattice.layers, 1);
  beads.reserve(std::size_t(layers) * std::size_t(lattice.rows) * std::size_t(lattice.columns));
  for (int l = 0; l < layers; ++l) {
    const double stacking = double(l % positions);
    for (int r = 0; r < lattice.rows; ++r)
      for (int c = 0; c < lattice.columns; ++c) {
        const double shift = close_packed && r % 2 == 1 ? a : 0.0;
        beads.push_back({vector_of({2.0 * a * c + shift + stacking * a,
                                    row_pitch * r + stacking * a / std::sqrt(3.0), layer_pitch * l},
                                   d),
                         a, lattice.material});
      }
  }
  return beads;
}

TouchIndex::TouchIndex(const std::vector<Body>& beads, int dimension, double touching)
    : touching_(touching) {
  double largest = 0.0;
  for (const Body& bead : beads) largest = std::max(largest, bead.radius);
  std::map<int, std::vector<std::size_t>> by_class;  // class k: radii in (R / 2^(k+1), R / 2^k]
  for (std::size_t i = 0; i < beads.size(); ++i)
    by_class[int(std::floor(std::log2(largest / beads[i].radius)))].push_back(i);
  for (const auto& [k, members] : by_class) {
    double radius = 0.0;
    for (std::size_t i : members) radius = std::max(radius, beads[i].radius);
    RadiusClass& c = classes_.emplace_back(
        RadiusClass{radius, granular::CellGrid(2.0 * radius * (1.0 + touching), dimension)});
    for (std::size_t i : members) c.grid.insert(std::int32_t(i), point_of(beads[i].centre));
  }
}

std::vector<Eigen::Index> TouchIndex::candidates(const Vector& centre, double radius) const {
  std::vector<Eigen::Index> found;
  for (const RadiusClass& c : classes_)
    c.grid.visit_near(point_of(centre), (radius + c.largest_radius) * (1.0 + touching_),
                      [&](std::int32_t j) { found.push_back(j); });
  std::sort(found.begin(), found.end());
  return found;
}

double bead_bytes(int dimension) {
  return granular::model_bytes(1.0, 3.0 * (dimension - 1), dimension);
}

std::filesystem::path bead_file(const BeadListSpec& list, const std::filesystem::path& directory) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path root = fs::weakly_canonical(fs::absolute(directory, error), error);
  const fs::path path = fs::weakly_canonical(fs::absolute(directory / list.file, error), error);
  const auto [outside, _] = std::mismatch(root.begin(), root.end(), path.begin(), path.end());
  if (list.file.empty() || outside != root.end())
    throw InvalidInput("beads.file = " + kernel::json_excerpt(nlohmann::json(list.file)) +
                       " is not inside " + root.string() +
                       "; allowed: a file in the scene's directory or below it (--data-dir, or "
                       "data_dir= in Python, chooses another directory)");
  const fs::file_status status = fs::status(path, error);
  if (!fs::exists(status)) throw InvalidInput("beads.file: " + path.string() + " does not exist");
  if (!fs::is_regular_file(status))
    throw InvalidInput("beads.file: " + path.string() +
                       " is not a regular file (a directory, device or pipe); allowed: a CSV file");
  return path;
}

namespace {

// A bead list's columns: the centre and radius, optionally the velocity, then the spin.
struct Columns {
  int dimension;
  int count;  // dimension + 1, + dimension with velocities, + 1 or 3 with spins
  std::vector<std::string> names;
};

// The headers a bead list may have, each with its columns.
const std::vector<Columns>& bead_list_headers() {
  static const std::vector<Columns> kHeaders = {
      {2, 3, {"x", "y", "radius"}},
      {2, 5, {"x", "y", "radius", "vx", "vy"}},
      {2, 6, {"x", "y", "radius", "vx", "vy", "wz"}},
      {3, 4, {"x", "y", "z", "radius"}},
      {3, 7, {"x", "y", "z", "radius", "vx", "vy", "vz"}},
      {3, 10, {"x", "y", "z", "radius", "vx", "vy", "vz", "wx", "wy", "wz"}}};
  return kHeaders;
}

// "x,y,radius": the header of these columns
std::string line_of(const std::vector<std::string>& names) {
  std::string line = names[0];
  for (std::size_t k = 1; k < names.size(); ++k) (line += ",") += names[k];
  return line;
}

// A cell of the list as a number: the whole cell, spaces aside, and finite.
std::optional<double> number_of(std::string cell) {
  const std::size_t first = cell.find_first_not_of(" \t\r");
  const std::size_t last = cell.find_last_not_of(" \t\r");
  if (first == std::string::npos) return std::nullopt;
  cell = cell.substr(first, last - first + 1);
  char* end = nullptr;
  const double value = std::strtod(cell.c_str(), &end);
  if (end != cell.c_str() + cell.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

// The bead of a line's values, in the columns' order.
Body bead_of(const Columns& columns, const double* values, const granular::Material& material,
             std::size_t line) {
  const int d = columns.dimension;
  Body bead{.centre = vector_of({values[0], values[1], values[2]}, d),
            .radius = values[d],
            .material = material,
            .line = line};
  if (columns.count > d + 1)
    bead.velocity = vector_of({values[d + 1], values[d + 2], values[d + 3]}, d);
  if (columns.count == 6) bead.spin.z() = values[5];
  if (columns.count == 10) bead.spin = Eigen::Vector3d(values[7], values[8], values[9]);
  return bead;
}

}  // namespace

std::vector<Body> listed_beads(const BeadListSpec& list, const std::filesystem::path& directory,
                               const granular::RunLimits& limits) {
  const std::filesystem::path path = bead_file(list, directory);
  std::ifstream in(path);
  if (!in) throw InvalidInput("beads.file: cannot open " + path.string() + " for reading");
  auto fail = [&](std::size_t line, const std::string& what) -> void {
    throw InvalidInput(path.string() + " line " + std::to_string(line) + ": " + what);
  };
  std::string line;
  std::getline(in, line);
  if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte-order mark
  if (line.find_last_not_of(" \t\r") != std::string::npos)
    line.erase(line.find_last_not_of(" \t\r") + 1);
  const Columns* header = nullptr;
  std::string allowed;
  for (const Columns& columns : bead_list_headers()) {
    if (line == line_of(columns.names)) header = &columns;
    allowed += (allowed.empty() ? "" : "; ") + line_of(columns.names);
  }
  if (!header) fail(1, "is not the header; allowed: " + allowed + " (m, m/s, rad/s)");
  const std::vector<std::string>& names = header->names;
  std::vector<Body> beads;
  for (std::size_t number = 2; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream fields(line);
    std::string cell;
    double values[10];
    int count = 0;
    for (; std::getline(fields, cell, ','); ++count) {
      if (count == header->count)
        fail(number,
             "more than " + std::to_string(header->count) + " columns; allowed: " + line_of(names));
      const std::optional<double> value = number_of(cell);
      if (!value) fail(number, "column " + names[std::size_t(count)] + " is not a finite number");
      values[count] = *value;
    }
    if (count != header->count)
      fail(number, std::to_string(count) + " columns; allowed: " + line_of(names));
    const double radius = values[header->dimension];
    if (!(radius > 0.0)) fail(number, invalid_value_message("radius", radius, "> 0 (m)"));
    beads.push_back(bead_of(*header, values, list.material, number));
    const double bytes = double(beads.size()) * bead_bytes(header->dimension);
    if (bytes > limits.memory_bytes())  // every bead, the message only when it is needed
      granular::check_memory(
          bytes, "beads.file (" + std::to_string(beads.size()) + " beads so far)", limits);
  }
  if (beads.empty())
    throw InvalidInput(path.string() + ": the bead list is empty; allowed: at least one bead");
  return beads;
}

}  // namespace mimpact::packings
