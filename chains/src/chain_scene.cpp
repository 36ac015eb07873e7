#include "mimpact/chains/chain_scene.hpp"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "mimpact/common/error.hpp"

namespace mimpact::chains {

namespace {

using nlohmann::json;

// a bound on the beads of a chain, so that every index fits an int (the memory a run may take
// bounds them further: RunLimits)
constexpr std::int64_t kMostBeads = 100'000'000;

// What the field lists cannot say alone: counts, pairings, and fields that depend on others.
void check_bodies(const ChainScene& scene, const granular::SceneChecks& checks) {
  const ChainSpec& chain = scene.chain;
  if (chain.segments.empty() == chain.beads.empty())
    checks.fail(chain.segments.empty()
                    ? "chain needs its beads: \"segments\", a non-empty array of runs of beads, "
                      "or \"beads\", a non-empty array of beads"
                    : "chain has both \"segments\" and \"beads\"; allowed: one of them");
  std::int64_t beads = std::int64_t(chain.beads.size());
  for (const SegmentSpec& segment : chain.segments) beads += segment.count;
  if (beads > kMostBeads)
    checks.fail(chain.key() + " hold " + std::to_string(beads) +
                " beads in all; allowed: at most " + std::to_string(kMostBeads));
  if (scene.strikers.empty() || scene.strikers.size() > 2)
    checks.fail("strikers must be an array of one or two strikers");
  if (scene.strikers.size() == 2 && scene.strikers[0].side == scene.strikers[1].side)
    checks.fail(
        "strikers[0] and strikers[1] are both on the same side; allowed: one striker per side");
  if (scene.wall && scene.striker(Side::right))
    checks.fail(
        "a right striker and a wall: the wall touches the last bead on the right; allowed: one "
        "of them");
  scene.contact.check(checks);
}

void check_record(const ChainScene& scene, const granular::SceneChecks& checks) {
  auto check = [&](const std::vector<int>& indices, const std::string& key, int count,
                   const std::string& what) {
    for (std::size_t k = 0; k < indices.size(); ++k)
      if (indices[k] >= count)
        checks.fail(
            invalid_value_message("record." + key + "[" + std::to_string(k) + "]", indices[k],
                                  "a " + what + " index in [0, " + std::to_string(count) + ")"));
  };
  check(scene.record.contacts, "contacts", scene.contact_count(), "contact");
  check(scene.record.bodies, "bodies", scene.body_count(), "body");
}

// A static force only the compliant method, with a wall, can hold.
void check_precompression(const ChainScene& scene, const granular::SceneChecks& checks) {
  if (scene.precompression == 0.0) return;
  if (scene.method == granular::Method::lzb)
    checks.fail("precompression = " + to_text(scene.precompression) +
                " N needs method \"compliant\" (or \"auto\"): the LZB impact starts from beads "
                "that barely touch");
  if (!scene.wall) checks.fail("precompression needs a wall for the chain to be pressed against");
  if (!scene.compliant.end_time)
    checks.fail(
        "missing field compliant.end_time: a precompressed chain never comes apart, so the run "
        "needs an end");
}

}  // namespace

ChainScene read_chain_scene(json document, const std::string& source,
                            const kernel::JsonLocations* locations) {
  const granular::SceneChecks checks(source);
  granular::lend_material(document, {"/chain/segments", "/chain/beads", "/strikers", "/wall"},
                          source);
  ChainScene scene;
  kernel::read_fields(
      document, scene,
      {.name = source, .unknown = "key", .top = "the top level", .locations = locations});
  scene.source = source;
  check_bodies(scene, checks);
  granular::check_accuracy_alone(document, checks);
  scene.impact = granular::resolve_impact(scene.impact, scene.method, {}, source);
  check_record(scene, checks);
  check_precompression(scene, checks);
  scene.compliant.check_tolerance(false, checks);  // a chain's gaps are linear: frozen
  if (scene.method == granular::Method::compliant ||
      (scene.method == granular::Method::automatic && scene.precompression > 0.0))
    granular::check_compliant_restitution(scene.contact, checks);
  return scene;
}

ChainScene parse_chain_scene(std::string_view text, const std::string& source) {
  kernel::JsonDocument document = granular::parse_scene_document(text, source);
  return read_chain_scene(std::move(document.value), source, &document.locations);
}

int ChainScene::bead_count() const {
  int count = int(chain.beads.size());
  for (const SegmentSpec& segment : chain.segments) count += segment.count;
  return count;
}

const StrikerSpec* ChainScene::striker(Side side) const {
  for (const StrikerSpec& striker : strikers)
    if (striker.side == side) return &striker;
  return nullptr;
}

ChainScene load_chain_scene(const std::filesystem::path& path) {
  return parse_chain_scene(granular::read_scene_file(path), path.string());
}

}  // namespace mimpact::chains
