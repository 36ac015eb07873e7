#include "mimpact/chains/chain_scene.hpp"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "mimpact/common/error.hpp"

namespace mimpact::chains {

namespace {

using nlohmann::json;

// rows of forces.csv a compliant run may write: 1e8 rows of a few contacts are gigabytes
constexpr double kMaxRecordedSamples = 1e8;

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
  scene.contact.check(checks);
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

void lend_material(nlohmann::json& document, std::initializer_list<const char*> bodies,
                   const std::string& source) {
  if (!document.is_object()) return;
  auto lend = [&](json& body, const std::string& path) {
    if (!body.is_object() || body.contains("material")) return;
    if (!document.contains("material"))
      throw InvalidInput(source + ": missing field " + path +
                         ".material (and no top-level \"material\" to fall back on)");
    body["material"] = document["material"];
  };
  for (const char* pointer : bodies) {
    const json::json_pointer at(pointer);
    if (!document.contains(at)) continue;
    // "/chain/segments" is named chain.segments in messages
    std::string path = std::string(pointer).substr(1);
    std::replace(path.begin(), path.end(), '/', '.');
    json& bodies_at = document[at];
    if (!bodies_at.is_array()) {
      lend(bodies_at, path);
      continue;
    }
    for (std::size_t k = 0; k < bodies_at.size(); ++k)
      lend(bodies_at[k], path + "[" + std::to_string(k) + "]");
  }
}

void ContactSpec::check(const SceneChecks& checks) const {
  if (!stiffness && exponent != 1.5)
    checks.fail(
        "missing field contact.stiffness: the Hertz stiffness holds for exponent 1.5 only, and "
        "contact.exponent = " +
        to_text(exponent));
}

double impulse_step(const ContactModel& model, std::optional<double> chosen,
                    std::optional<double> scene_value, std::int64_t max_steps,
                    const std::string& field) {
  const std::optional<double> delta_p = chosen ? chosen : scene_value;
  if (!delta_p)
    throw InvalidInput(
        "missing field impact.delta_p (the impulse steps' principal step, N s); or choose "
        "\"integrator\": \"adaptive\" with a tolerance");
  check_delta_p(model, *delta_p, max_steps, field);
  return *delta_p;
}

std::optional<double> take_delta_p(kernel::Parameters& impact, const std::string& source) {
  const plugins::LzbImpactOptions options = kernel::options_from<plugins::LzbImpactOptions>(
      impact, {.name = source, .path = "impact", .unknown = "key"});
  if (!impact.contains("delta_p")) return std::nullopt;
  if (options.integrator == plugins::LzbIntegrator::adaptive)
    throw InvalidInput(source + ": impact.delta_p = " + to_text(options.impulse_steps.delta_p) +
                       " is the step of the impulse-step integrator; allowed with "
                       "\"integrator\": \"adaptive\": impact.tolerance");
  impact.erase("delta_p");
  return options.impulse_steps.delta_p;
}

nlohmann::json parse_scene_document(std::string_view text, const std::string& source) {
  try {
    return json::parse(text, nullptr, true, /*ignore_comments=*/true);
  } catch (const json::parse_error& error) {
    throw InvalidInput(source + ": malformed JSON: " + error.what());
  }
}

ChainScene parse_chain_scene(std::string_view text, const std::string& source) {
  const SceneChecks checks(source);
  json document = parse_scene_document(text, source);
  lend_material(document, {"/chain/segments", "/strikers", "/wall"}, source);
  ChainScene scene;
  kernel::read_fields(document, scene, {.name = source, .unknown = "key", .top = "the top level"});
  check_bodies(scene, checks);
  scene.delta_p = take_delta_p(scene.impact, source);
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

plugins::LzbImpactOptions lzb_impact_options(const kernel::Parameters& impact,
                                             std::optional<double> delta_p) {
  plugins::LzbImpactOptions options =
      kernel::options_from<plugins::LzbImpactOptions>(impact, {.name = "impact"});
  if (delta_p) options.impulse_steps.delta_p = *delta_p;
  return options;
}

plugins::LzbImpactOptions ChainScene::impact_options() const {
  return lzb_impact_options(impact, delta_p);
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
