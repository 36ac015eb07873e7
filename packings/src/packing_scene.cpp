#include "mimpact/packings/packing_scene.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

#include "mimpact/common/error.hpp"

namespace mimpact::packings {

namespace {

using granular::SceneChecks;
using nlohmann::json;

// A pair [x, y] of finite numbers, or InvalidInput naming the field.
void check_pair(const std::vector<double>& value, const std::string& field, const char* what,
                const SceneChecks& checks) {
  if (value.size() != 2)
    checks.fail(field + " has " + std::to_string(value.size()) + " entries; allowed: " + what);
  for (std::size_t k = 0; k < 2; ++k)
    if (!std::isfinite(value[k]))
      checks.fail(invalid_value_message(field + "[" + std::to_string(k) + "]", value[k], what));
}

void check_packing(const PackingScene& scene, const SceneChecks& checks) {
  if (scene.lattice.has_value() == scene.beads.has_value())
    checks.fail(std::string(scene.lattice ? "both \"lattice\" and \"beads\""
                                          : "neither "
                                            "\"lattice\" nor "
                                            "\"beads\"") +
                "; allowed: one of them (a lattice of equal beads, or a CSV bead list)");
  if (scene.lattice && double(scene.lattice->rows) * scene.lattice->columns > 1e8)
    checks.fail("lattice.rows x lattice.columns = " +
                to_text(double(scene.lattice->rows) * scene.lattice->columns) +
                " beads; allowed: at most 1e8");
  scene.contact.check(checks);
  if (scene.compliant.gaps == granular::Gaps::frozen &&
      scene.compliant.geometry == granular::Geometry::moving)
    checks.fail(
        "compliant.gaps = \"frozen\" with compliant.geometry = \"moving\"; allowed: frozen "
        "gaps in the frozen geometry only (the moving geometry's gaps are the beads' own)");
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
                  "; allowed: \"side\" (bottom, top, left, right), or \"point\" and \"normal\"");
    if (!line) continue;
    check_pair(wall.point, path + ".point", "[x, y], finite (m)", checks);
    check_pair(wall.normal, path + ".normal", "[nx, ny], finite and not zero", checks);
    if (std::hypot(wall.normal[0], wall.normal[1]) == 0.0)
      checks.fail(path + ".normal = [0, 0] is invalid; allowed: [nx, ny], not zero");
  }
}

void check_strikers(const PackingScene& scene, const SceneChecks& checks) {
  if (scene.strikers.empty()) checks.fail("strikers must be an array of at least one striker");
  for (std::size_t k = 0; k < scene.strikers.size(); ++k) {
    const StrikerSpec& striker = scene.strikers[k];
    const std::string path = "strikers[" + std::to_string(k) + "]";
    check_pair(striker.velocity, path + ".velocity", "[vx, vy], finite and not zero (m/s)", checks);
    const double speed = std::hypot(striker.velocity[0], striker.velocity[1]);
    if (!(speed >= granular::kSlowestStriker))
      checks.fail(path + ".velocity = [" + to_text(striker.velocity[0]) + ", " +
                  to_text(striker.velocity[1]) +
                  "] is invalid; allowed: [vx, vy] of speed >= 1e-100 m/s (below, m v^2 "
                  "underflows double precision)");
    const std::size_t wanted = scene.lattice ? 2 : 1;
    if (striker.target.size() != wanted)
      checks.fail(path + ".target has " + std::to_string(striker.target.size()) +
                  " entries; allowed: " +
                  (scene.lattice ? "[row, column] in the lattice" : "[bead] in the bead list"));
    if (scene.lattice) {
      const int limits[2] = {scene.lattice->rows, scene.lattice->columns};
      const char* names[2] = {"row", "column"};
      for (std::size_t i = 0; i < 2; ++i)
        if (striker.target[i] >= limits[i])
          checks.fail(invalid_value_message(
              path + ".target[" + std::to_string(i) + "]", striker.target[i],
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
  PackingScene scene;
  kernel::read_fields(
      document, scene,
      {.name = source, .unknown = "key", .top = "the top level", .locations = locations});
  scene.directory = directory;
  scene.source = source;
  check_packing(scene, checks);
  check_walls(scene, checks);
  check_strikers(scene, checks);
  scene.impact = granular::resolve_impact(scene.impact, scene.method, {}, source);
  return scene;
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
