#include "mimpact/packings/packing_scene.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "mimpact/common/error.hpp"
#include "mimpact/kernel/json_document.hpp"

namespace mimpact::packings {

namespace {

using granular::SceneChecks;
using nlohmann::json;

// A vector of 2 or 3 finite numbers, or InvalidInput naming the field.
void check_vector(const std::vector<double>& value, const std::string& field, const char* what,
                  const SceneChecks& checks) {
  if (value.size() != 2 && value.size() != 3)
    checks.fail(field + " has " + std::to_string(value.size()) + " entries; allowed: " + what);
  for (std::size_t k = 0; k < value.size(); ++k)
    if (!std::isfinite(value[k]))
      checks.fail(invalid_value_message(field + "[" + std::to_string(k) + "]", value[k], what));
}

std::string type_name(LatticeType type) {
  for (const auto& [value, name] : enum_names(type))
    if (value == type) return std::string(name);
  return "?";
}

// the length of a vector of any finite components (a scaled norm: [0, 1e-170] is not 0)
double norm(const std::vector<double>& value) {
  return Eigen::Map<const Eigen::VectorXd>(value.data(), Eigen::Index(value.size())).stableNorm();
}

std::string vector_text(const std::vector<double>& value) {
  std::string text = "[";
  for (std::size_t k = 0; k < value.size(); ++k) {
    if (k > 0) text += ", ";
    text += to_text(value[k]);
  }
  return text + "]";
}

void check_packing(const PackingScene& scene, const SceneChecks& checks) {
  if (scene.lattice.has_value() == scene.beads.has_value())
    checks.fail(std::string(scene.lattice ? "both \"lattice\" and \"beads\""
                                          : "neither "
                                            "\"lattice\" nor "
                                            "\"beads\"") +
                "; allowed: one of them (a lattice of equal beads, or a CSV bead list)");
  if (scene.lattice) {
    const LatticeSpec& lattice = *scene.lattice;
    const bool solid = lattice_dimension(lattice.type) == 3;
    if (solid && lattice.layers == 0)
      checks.fail("lattice.layers is missing: a " + type_name(lattice.type) +
                  " lattice is three-dimensional; allowed: an integer >= 1");
    if (!solid && lattice.layers != 0)
      checks.fail("lattice.layers = " + std::to_string(lattice.layers) + " for a " +
                  type_name(lattice.type) +
                  " lattice, which is planar; allowed: layers with simple-cubic, fcc or hcp only");
    const double count = double(std::max(lattice.layers, 1)) * lattice.rows * lattice.columns;
    if (count > 1e8)
      checks.fail("lattice.layers x lattice.rows x lattice.columns = " + to_text(count) +
                  " beads; allowed: at most 1e8");
  }
  scene.contact.check(checks);
  if (scene.compliant.gaps == granular::Gaps::frozen &&
      scene.compliant.geometry == granular::Geometry::moving)
    checks.fail(
        "compliant.gaps = \"frozen\" with compliant.geometry = \"moving\"; allowed: frozen "
        "gaps in the frozen geometry only (the moving geometry's gaps are the beads' own)");
  scene.compliant.check_tolerance(scene.compliant.geometry == granular::Geometry::moving, checks);
  if (scene.method == granular::Method::compliant)
    granular::check_compliant_restitution(scene.contact, checks);
}

// the names of the scene's materials, each once
std::vector<std::string> material_names(const PackingScene& scene) {
  std::vector<std::string> names;
  auto add = [&](const granular::Material& material) {
    if (!material.name.empty() &&
        std::find(names.begin(), names.end(), material.name) == names.end())
      names.push_back(material.name);
  };
  if (scene.material) add(*scene.material);
  if (scene.lattice) add(scene.lattice->material);
  if (scene.beads) add(scene.beads->material);
  for (const WallSpec& wall : scene.walls) add(wall.material);
  for (const StrikerSpec& striker : scene.strikers) add(striker.material);
  return names;
}

void check_walls(const PackingScene& scene, const SceneChecks& checks) {
  for (std::size_t k = 0; k < scene.walls.size(); ++k) {
    const WallSpec& wall = scene.walls[k];
    const std::string path = "walls[" + std::to_string(k) + "]";
    const bool line = !wall.point.empty() || !wall.normal.empty();
    if (wall.side.has_value() == line)
      checks.fail(path +
                  (wall.side ? " has both a side and a point or normal"
                             : " has neither a side nor a point and normal") +
                  "; allowed: \"side\" (bottom, top, left, right, back, front), or \"point\" and "
                  "\"normal\"");
    if (!line) continue;
    check_vector(wall.point, path + ".point", "[x, y] or [x, y, z], finite (m)", checks);
    check_vector(wall.normal, path + ".normal", "[nx, ny] or [nx, ny, nz], finite and not zero",
                 checks);
    if (norm(wall.normal) == 0.0)
      checks.fail(path + ".normal = " + vector_text(wall.normal) +
                  " is invalid; allowed: a normal of length > 0");
  }
}

// A striker's offset or spin given as a number: [number], the plane's form of the vector;
// neither a number nor an array is refused as such.
void numbers_as_vectors(json& document, const SceneChecks& checks) {
  json* strikers =
      document.is_object() && document.contains("strikers") ? &document["strikers"] : nullptr;
  if (!strikers || !strikers->is_array()) return;
  for (std::size_t k = 0; k < strikers->size(); ++k) {
    json& striker = (*strikers)[k];
    for (const char* key : {"offset", "spin"}) {
      if (!striker.is_object() || !striker.contains(key)) continue;
      json& value = striker[key];
      if (value.is_number()) value = json::array({value});
      if (!value.is_array())
        checks.fail("strikers[" + std::to_string(k) + "]." + key + " = " +
                    kernel::json_excerpt(value) +
                    " is invalid; allowed: " + (key == std::string("offset") ? "m" : "rad/s") +
                    ", a number in the plane, [x, y, z] in space");
    }
  }
}

// An offset or spin: finite components.
void check_finite(const std::vector<double>& value, const std::string& field, const char* what,
                  const SceneChecks& checks) {
  for (std::size_t k = 0; k < value.size(); ++k)
    if (!std::isfinite(value[k]))
      checks.fail(invalid_value_message(field + "[" + std::to_string(k) + "]", value[k], what));
}

void check_strikers(const PackingScene& scene, const SceneChecks& checks) {
  if (scene.strikers.empty()) checks.fail("strikers must be an array of at least one striker");
  for (std::size_t k = 0; k < scene.strikers.size(); ++k) {
    const StrikerSpec& striker = scene.strikers[k];
    const std::string path = "strikers[" + std::to_string(k) + "]";
    check_vector(striker.velocity, path + ".velocity",
                 "[vx, vy] or [vx, vy, vz], finite and not zero (m/s)", checks);
    if (!(norm(striker.velocity) >= granular::kSlowestStriker))
      checks.fail(path + ".velocity = " + vector_text(striker.velocity) +
                  " is invalid; allowed: a velocity of speed >= 1e-100 m/s (below, m v^2 "
                  "underflows double precision)");
    check_finite(striker.offset, path + ".offset", "a finite offset (m)", checks);
    check_finite(striker.spin, path + ".spin", "a finite angular velocity (rad/s)", checks);
    const bool solid = scene.lattice && lattice_dimension(scene.lattice->type) == 3;
    const std::size_t wanted = scene.lattice ? (solid ? 3 : 2) : 1;
    if (striker.target.size() != wanted)
      checks.fail(path + ".target has " + std::to_string(striker.target.size()) +
                  " entries; allowed: " +
                  (!scene.lattice ? "[bead] in the bead list"
                   : solid        ? "[layer, row, column] in the lattice"
                                  : "[row, column] in the lattice"));
    if (scene.lattice) {
      const int limits[3] = {scene.lattice->layers, scene.lattice->rows, scene.lattice->columns};
      const char* names[3] = {"layer", "row", "column"};
      const std::size_t first = solid ? 0 : 1;  // the planar target has no layer
      for (std::size_t i = first; i < 3; ++i)
        if (striker.target[i - first] >= limits[i])
          checks.fail(invalid_value_message(
              path + ".target[" + std::to_string(i - first) + "]", striker.target[i - first],
              std::string("a ") + names[i] + " in [0, " + std::to_string(limits[i]) +
                  "): the striker is aimed at nothing"));
    }
  }
}

}  // namespace

PackingScene read_packing_scene(json document, const std::string& source,
                                const std::filesystem::path& directory,
                                const kernel::JsonLocations* locations) {
  const SceneChecks checks(source);
  granular::lend_material(document, {"/lattice", "/beads", "/walls", "/strikers"}, source);
  numbers_as_vectors(document, checks);
  PackingScene scene;
  kernel::read_fields(
      document, scene,
      {.name = source, .unknown = "key", .top = "the top level", .locations = locations});
  scene.directory = directory;
  scene.source = source;
  check_packing(scene, checks);
  granular::check_accuracy_alone(document, checks);
  scene.contact.check_pairs(material_names(scene), checks);
  check_walls(scene, checks);
  check_strikers(scene, checks);
  scene.impact = granular::resolve_impact(scene.impact, scene.method, {}, source);
  return scene;
}

void check_dimension(const PackingScene& scene, int dimension) {
  const SceneChecks checks(scene.source);
  const std::string packing =
      dimension == 2 ? "a planar packing: [x, y]" : "a three-dimensional packing: [x, y, z]";
  auto check = [&](const std::vector<double>& value, const std::string& field) {
    if (!value.empty() && int(value.size()) != dimension)
      checks.fail(field + " = " + vector_text(value) + " has " + std::to_string(value.size()) +
                  " components; allowed: " + std::to_string(dimension) + " in " + packing);
  };
  for (std::size_t k = 0; k < scene.walls.size(); ++k) {
    const std::string path = "walls[" + std::to_string(k) + "]";
    check(scene.walls[k].point, path + ".point");
    check(scene.walls[k].normal, path + ".normal");
    if (dimension == 2 && scene.walls[k].side && *scene.walls[k].side >= WallSide::back)
      checks.fail(path +
                  ".side is back or front in a planar packing; allowed: bottom, top, "
                  "left, right");
  }
  const std::string turning =
      dimension == 2 ? "a planar packing: a number" : "a three-dimensional packing: [x, y, z]";
  auto check_turning = [&](const std::vector<double>& value, const std::string& field) {
    const std::size_t wanted = dimension == 2 ? 1 : 3;
    if (!value.empty() && value.size() != wanted)
      checks.fail(field + " = " + vector_text(value) + " has " + std::to_string(value.size()) +
                  " components; allowed: " + std::to_string(wanted) + " in " + turning);
  };
  for (std::size_t k = 0; k < scene.strikers.size(); ++k) {
    const StrikerSpec& striker = scene.strikers[k];
    const std::string path = "strikers[" + std::to_string(k) + "]";
    check(striker.velocity, path + ".velocity");
    check_turning(striker.offset, path + ".offset");
    check_turning(striker.spin, path + ".spin");
    if (dimension == 3 && !striker.offset.empty()) {
      // the offset lies across the path: its share along the velocity is round-off
      const Eigen::Vector3d offset(striker.offset.data()), velocity(striker.velocity.data());
      if (std::abs(offset.stableNormalized().dot(velocity.stableNormalized())) > 1e-9)
        checks.fail(path + ".offset = " + vector_text(striker.offset) +
                    " is not perpendicular to its velocity " + vector_text(striker.velocity) +
                    "; allowed: an offset across the striker's path (offset . velocity = 0)");
    }
  }
}

PackingScene parse_packing_scene(std::string_view text, const std::string& source,
                                 const std::filesystem::path& directory) {
  kernel::JsonDocument document = granular::parse_scene_document(text, source);
  return read_packing_scene(std::move(document.value), source, directory, &document.locations);
}

PackingScene load_packing_scene(const std::filesystem::path& path) {
  return parse_packing_scene(granular::read_scene_file(path), path.string(),
                             path.has_parent_path() ? path.parent_path() : ".");
}

granular::RecordSpec PackingScene::run_record() const {
  return {.contacts = record.contacts,
          .bodies = record.beads,
          .every = record.every,
          .interval = record.interval};
}

}  // namespace mimpact::packings
