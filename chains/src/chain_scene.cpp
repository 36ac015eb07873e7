#include "mimpact/chains/chain_scene.hpp"

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "mimpact/common/error.hpp"

namespace mimpact::chains {

namespace {

using nlohmann::json;

// rows of forces.csv a compliant run may write: 1e8 rows of a few contacts are gigabytes
constexpr double kMaxRecordedSamples = 1e8;

class SceneChecks {
 public:
  explicit SceneChecks(const std::string& source) : source_(source) {}
  [[noreturn]] void fail(const std::string& what) const {
    throw InvalidInput(source_ + ": " + what);
  }

 private:
  const std::string& source_;
};

// A bead, striker or wall without "material" takes the scene's: copied into the document
// before it is read, so that the one field list reads every body alike.
void lend_material(json& document, const SceneChecks& checks) {
  if (!document.is_object()) return;
  auto lend = [&](json& body, const std::string& path) {
    if (!body.is_object() || body.contains("material")) return;
    if (!document.contains("material"))
      checks.fail("missing field " + path +
                  ".material (and no top-level \"material\" to fall back on)");
    body["material"] = document["material"];
  };
  auto each = [&](json* list, const std::string& path) {
    if (!list || !list->is_array()) return;
    for (std::size_t k = 0; k < list->size(); ++k)
      lend((*list)[k], path + "[" + std::to_string(k) + "]");
  };
  if (document.contains("chain") && document["chain"].is_object() &&
      document["chain"].contains("segments"))
    each(&document["chain"]["segments"], "chain.segments");
  if (document.contains("strikers")) each(&document["strikers"], "strikers");
  if (document.contains("wall")) lend(document["wall"], "wall");
}

// What the field lists cannot say alone: counts, pairings, and fields that depend on others.
void check_bodies(const ChainScene& scene, const SceneChecks& checks) {
  if (scene.chain.segments.empty())
    checks.fail("chain.segments must be a non-empty array of segments");
  if (scene.strikers.empty() || scene.strikers.size() > 2)
    checks.fail("strikers must be an array of one or two strikers");
  if (scene.strikers.size() == 2 && scene.strikers[0].side == scene.strikers[1].side)
    checks.fail(
        "strikers[0] and strikers[1] are both on the same side; allowed: one striker per side");
  if (scene.wall && scene.striker(Side::right))
    checks.fail(
        "a right striker and a wall: the wall touches the last bead on the right; allowed: one "
        "of them");
  if (!scene.contact.stiffness && scene.contact.exponent != 1.5)
    checks.fail(
        "missing field contact.stiffness: the Hertz stiffness holds for exponent 1.5 only, and "
        "contact.exponent = " +
        to_text(scene.contact.exponent));
}

// "impact" is read as the "lzb" impact problem reads its parameters; delta_p is kept apart.
void split_delta_p(ChainScene& scene, const std::string& source) {
  const plugins::LzbImpactOptions options = kernel::options_from<plugins::LzbImpactOptions>(
      scene.impact, {.name = source, .path = "impact", .unknown = "key"});
  if (!scene.impact.contains("delta_p")) return;
  if (options.integrator == plugins::LzbIntegrator::adaptive)
    throw InvalidInput(source + ": impact.delta_p = " + to_text(options.impulse_steps.delta_p) +
                       " is the step of the impulse-step integrator; allowed with "
                       "\"integrator\": \"adaptive\": impact.tolerance");
  scene.delta_p = options.impulse_steps.delta_p;
  scene.impact.erase("delta_p");
}

void check_record(const ChainScene& scene, const SceneChecks& checks) {
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
  const double end_time = scene.compliant.end_time.value_or(1.0);
  const bool recording = !scene.record.contacts.empty() || !scene.record.bodies.empty();
  if (scene.method == Method::compliant && recording &&
      end_time / scene.record.interval > kMaxRecordedSamples)
    checks.fail(invalid_value_message("record.interval", scene.record.interval,
                                      ">= compliant.end_time / " + to_text(kMaxRecordedSamples) +
                                          " = " + to_text(end_time / kMaxRecordedSamples) +
                                          " s (at most " + to_text(kMaxRecordedSamples) +
                                          " rows)"));
}

// A static force only the compliant method, with a wall, can hold.
void check_precompression(const ChainScene& scene, const SceneChecks& checks) {
  if (scene.precompression == 0.0) return;
  if (scene.method != Method::compliant)
    checks.fail("precompression = " + to_text(scene.precompression) +
                " N needs method \"compliant\": the LZB impact starts from beads that barely "
                "touch");
  if (!scene.wall) checks.fail("precompression needs a wall for the chain to be pressed against");
  if (!scene.compliant.end_time)
    checks.fail(
        "missing field compliant.end_time: a precompressed chain never comes apart, so the run "
        "needs an end");
}

}  // namespace

ChainScene parse_chain_scene(std::string_view text, const std::string& source) {
  const SceneChecks checks(source);
  json document;
  try {
    document = json::parse(text, nullptr, true, /*ignore_comments=*/true);
  } catch (const json::parse_error& error) {
    checks.fail(std::string("malformed JSON: ") + error.what());
  }
  lend_material(document, checks);
  ChainScene scene;
  kernel::read_fields(document, scene, {.name = source, .unknown = "key", .top = "the top level"});
  check_bodies(scene, checks);
  split_delta_p(scene, source);
  check_record(scene, checks);
  check_precompression(scene, checks);
  return scene;
}

int ChainScene::bead_count() const {
  int count = 0;
  for (const SegmentSpec& segment : chain.segments) count += segment.count;
  return count;
}

const StrikerSpec* ChainScene::striker(Side side) const {
  for (const StrikerSpec& striker : strikers)
    if (striker.side == side) return &striker;
  return nullptr;
}

plugins::LzbImpactOptions ChainScene::impact_options() const {
  plugins::LzbImpactOptions options =
      kernel::options_from<plugins::LzbImpactOptions>(impact, {.name = "impact"});
  if (delta_p) options.impulse_steps.delta_p = *delta_p;
  return options;
}

bool ChainScene::adaptive() const {
  return method == Method::lzb && impact_options().integrator == plugins::LzbIntegrator::adaptive;
}

numerics::LzbOptions ChainScene::lzb_options(double impulse_step) const {
  numerics::LzbOptions options = impact_options().impulse_steps;
  options.delta_p = impulse_step;
  validate(options, "impact");
  return options;
}

std::string read_scene_file(const std::filesystem::path& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    throw InvalidInput(path.string() + ": is a directory; allowed: a scene file (JSON)");
  std::ifstream in(path);
  if (!in) throw InvalidInput(path.string() + ": cannot open the scene file for reading");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

ChainScene load_chain_scene(const std::filesystem::path& path) {
  return parse_chain_scene(read_scene_file(path), path.string());
}

}  // namespace mimpact::chains
