#include "mimpact/chain/chain_scene.hpp"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>

#include "mimpact/numerics/error.hpp"

namespace mimpact::chain {

namespace {

using nlohmann::json;

// Reads fields of one JSON object, every error naming the source and the field's path.
class ObjectReader {
 public:
  ObjectReader(const json& object, std::string path, const std::string& source)
      : object_(object), path_(std::move(path)), source_(source) {
    if (!object_.is_object()) fail(name() + " is " + std::string(object_.type_name()) +
                                   "; allowed: an object {...}");
  }

  void allow_only(std::initializer_list<std::string_view> keys) const {
    for (const auto& item : object_.items()) {
      bool known = false;
      for (std::string_view key : keys) known = known || item.key() == key;
      if (!known) {
        std::string allowed;
        for (std::string_view key : keys) allowed += (allowed.empty() ? "" : ", ") + std::string(key);
        fail("unknown key \"" + item.key() + "\" in " + name() + "; allowed: " + allowed);
      }
    }
  }

  bool has(const std::string& key) const { return object_.contains(key); }
  std::string field(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
  }
  const json& at(const std::string& key) const {
    if (!has(key)) fail("missing field " + field(key));
    return object_.at(key);
  }

  // A number satisfying `allowed` (described by `allowed_text`).
  double number(const std::string& key, const std::function<bool(double)>& allowed,
                const std::string& allowed_text) const {
    const json& value = at(key);
    if (!value.is_number())
      fail(field(key) + " is " + std::string(value.type_name()) + "; allowed: a number, " +
           allowed_text);
    const double x = value.get<double>();
    if (!(std::isfinite(x) && allowed(x)))
      fail(invalid_value_message(field(key), x, allowed_text));
    return x;
  }
  double number_or(const std::string& key, double fallback,
                   const std::function<bool(double)>& allowed,
                   const std::string& allowed_text) const {
    return has(key) ? number(key, allowed, allowed_text) : fallback;
  }

  std::string text(const std::string& key) const {
    const json& value = at(key);
    if (!value.is_string())
      fail(field(key) + " is " + std::string(value.type_name()) + "; allowed: a string");
    return value.get<std::string>();
  }

  [[noreturn]] void fail(const std::string& what) const { throw InvalidInput(source_ + ": " + what); }

 private:
  std::string name() const { return path_.empty() ? "the top level" : path_; }

  const json& object_;
  std::string path_;
  const std::string& source_;
};

bool positive(double x) { return x > 0.0; }

// rows of forces.csv a compliant run may write: 1e8 rows of a few contacts are gigabytes
constexpr double kMaxRecordedSamples = 1e8;

Material read_material(const ObjectReader& parent, const std::string& key,
                       const std::string& source) {
  ObjectReader reader(parent.at(key), parent.field(key), source);
  reader.allow_only({"density", "young", "poisson"});
  Material material;
  material.density = reader.number("density", positive, "> 0 (kg/m^3)");
  material.young = reader.number("young", positive, "> 0 (Pa)");
  material.poisson = reader.number("poisson", [](double x) { return x > -1.0 && x < 0.5; },
                                   "-1 < nu < 0.5");
  return material;
}

// The body's own material, else the scene's default one.
Material material_of(const ObjectReader& body, const std::optional<Material>& fallback,
                     const std::string& source) {
  if (body.has("material")) return read_material(body, "material", source);
  if (!fallback)
    body.fail("missing field " + body.field("material") +
              " (and no top-level \"material\" to fall back on)");
  return *fallback;
}

SegmentSpec read_segment(const json& value, const std::string& path,
                         const std::optional<Material>& fallback, const std::string& source) {
  ObjectReader reader(value, path, source);
  reader.allow_only({"count", "radius", "taper", "material"});
  SegmentSpec segment;
  segment.count = int(reader.number("count", [](double x) { return x >= 1 && x == std::floor(x) && x <= 1e8; },
                                    "an integer >= 1"));
  segment.radius = reader.number("radius", positive, "> 0 (m)");
  segment.taper = reader.number_or("taper", 0.0, [](double x) { return x >= 0.0 && x < 1.0; },
                                   "0 <= taper < 1");
  segment.material = material_of(reader, fallback, source);
  return segment;
}

StrikerSpec read_striker(const json& value, const std::string& path,
                         const std::optional<Material>& fallback, const std::string& source) {
  ObjectReader reader(value, path, source);
  reader.allow_only({"side", "radius", "velocity", "gap", "material"});
  StrikerSpec striker;
  const std::string side = reader.has("side") ? reader.text("side") : "left";
  if (side == "left") {
    striker.side = Side::left;
  } else if (side == "right") {
    striker.side = Side::right;
  } else {
    reader.fail(reader.field("side") + " = \"" + side + "\" is invalid; allowed: \"left\", \"right\"");
  }
  striker.radius = reader.number("radius", positive, "> 0 (m)");
  striker.velocity = reader.number("velocity", positive, "> 0 (m/s, towards the chain)");
  striker.gap = reader.number_or("gap", 0.0, [](double x) { return x >= 0.0; }, ">= 0 (m)");
  striker.material = material_of(reader, fallback, source);
  return striker;
}

std::vector<int> read_indices(const ObjectReader& reader, const std::string& key, int count,
                              const std::string& what) {
  std::vector<int> indices;
  if (!reader.has(key)) return indices;
  const json& list = reader.at(key);
  if (!list.is_array()) reader.fail(reader.field(key) + " must be an array of " + what + " indices");
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string field = reader.field(key) + "[" + std::to_string(k) + "]";
    // read wide: a narrowing read would wrap 4294967296 to a valid index
    if (!list[k].is_number_integer() || list[k].get<std::int64_t>() < 0 || list[k].get<std::int64_t>() >= count)
      reader.fail(field + " = " + list[k].dump() + " is invalid; allowed: a " + what +
                  " index in [0, " + std::to_string(count) + ")");
    indices.push_back(int(list[k].get<std::int64_t>()));
  }
  return indices;
}

ContactSpec read_contact(const ObjectReader& scene, const std::string& source) {
  ContactSpec contact;
  if (!scene.has("contact")) return contact;
  ObjectReader reader(scene.at("contact"), "contact", source);
  reader.allow_only({"model", "exponent", "restitution", "stiffness"});
  if (reader.has("model")) {
    const std::string model = reader.text("model");
    const auto parsed = numerics::compliance_model_from_string(model);
    if (!parsed)
      reader.fail("contact.model = \"" + model +
                  "\" is invalid; allowed: \"bi-stiffness\", \"mono-stiffness\"");
    contact.model = *parsed;
  }
  contact.exponent = reader.number_or("exponent", 1.5, [](double x) { return x > 0.0 && x <= 10.0; },
                                      "0 < eta <= 10 (1 linear, 3/2 Hertz)");
  contact.restitution = reader.number_or("restitution", 1.0,
                                         [](double x) { return x >= 0.0 && x <= 1.0; },
                                         "0 <= e <= 1");
  if (reader.has("stiffness"))
    contact.stiffness = reader.number("stiffness", positive, "> 0 (N/m^exponent)");
  else if (contact.exponent != 1.5)
    reader.fail("missing field contact.stiffness: the Hertz stiffness holds for exponent 1.5 "
                "only, and contact.exponent = " + to_text(contact.exponent));
  return contact;
}

// "impact": the LZB method's delta_p and fixed thresholds.
void read_impact(const ObjectReader& scene, const std::string& source, ChainScene& result) {
  if (!scene.has("impact")) return;
  ObjectReader impact(scene.at("impact"), "impact", source);
  impact.allow_only({"delta_p", "fixed_thresholds"});
  if (impact.has("delta_p")) result.delta_p = impact.number("delta_p", positive, "> 0 (N s)");
  if (impact.has("fixed_thresholds")) {
    ObjectReader fixed(impact.at("fixed_thresholds"), "impact.fixed_thresholds", source);
    fixed.allow_only({"velocity", "energy"});
    result.fixed_thresholds = numerics::LzbOptions::FixedThresholds{
        fixed.number("velocity", positive, "> 0 (m/s)"), fixed.number("energy", positive, "> 0 (J)")};
  }
}

// "record": the contacts and bodies written as time series, and how often.
void read_record(const ObjectReader& scene, const std::string& source, ChainScene& result) {
  if (!scene.has("record")) return;
  ObjectReader record(scene.at("record"), "record", source);
  record.allow_only({"contacts", "bodies", "every", "interval"});
  result.record.contacts = read_indices(record, "contacts", result.contact_count(), "contact");
  result.record.bodies = read_indices(record, "bodies", result.body_count(), "body");
  result.record.every = int(record.number_or(
      "every", 1, [](double x) { return x >= 1 && x == std::floor(x) && x < 2e9; },
      "an integer >= 1 (impulse steps)"));
  result.record.interval = record.number_or("interval", result.record.interval, positive, "> 0 (s)");
}

// "method" and the compliant method's "compliant" settings; needs "record" read first.
void read_method(const ObjectReader& scene, const std::string& source, ChainScene& result) {
  if (scene.has("method")) {
    const std::string method = scene.text("method");
    if (method == "lzb") {
      result.method = Method::lzb;
    } else if (method == "compliant") {
      result.method = Method::compliant;
    } else {
      scene.fail("method = \"" + method + "\" is invalid; allowed: \"lzb\", \"compliant\"");
    }
  }
  if (scene.has("compliant")) {
    ObjectReader compliant(scene.at("compliant"), "compliant", source);
    compliant.allow_only({"tolerance", "end_time"});
    // below 1e-14 the error estimate of Dormand-Prince drowns in round-off: the run never ends
    result.compliant.tolerance = compliant.number_or(
        "tolerance", result.compliant.tolerance, [](double x) { return x >= 1e-14 && x < 1.0; },
        "1e-14 <= tolerance < 1");
    if (compliant.has("end_time")) result.compliant.end_time = compliant.number("end_time", positive, "> 0 (s)");
  }
  const double end_time = result.compliant.end_time.value_or(1.0);
  const bool recording = !result.record.contacts.empty() || !result.record.bodies.empty();
  if (result.method == Method::compliant && recording && end_time / result.record.interval > kMaxRecordedSamples)
    scene.fail(invalid_value_message("record.interval", result.record.interval,
                                     ">= compliant.end_time / " + to_text(kMaxRecordedSamples) + " = " +
                                         to_text(end_time / kMaxRecordedSamples) + " s (at most " +
                                         to_text(kMaxRecordedSamples) + " rows)"));
}

// "precompression": a static force that only the compliant method, with a wall, can hold.
void read_precompression(const ObjectReader& scene, ChainScene& result) {
  result.precompression = scene.number_or("precompression", 0.0, [](double x) { return x >= 0.0; }, ">= 0 (N)");
  if (result.precompression == 0.0) return;
  if (result.method != Method::compliant)
    scene.fail("precompression = " + to_text(result.precompression) +
               " N needs method \"compliant\": the LZB impact starts from beads that barely touch");
  if (!result.wall) scene.fail("precompression needs a wall for the chain to be pressed against");
  if (!result.compliant.end_time)
    scene.fail("missing field compliant.end_time: a precompressed chain never comes apart, so the run needs an end");
}

}  // namespace

ChainScene parse_chain_scene(std::string_view text, const std::string& source) {
  json document;
  try {
    document = json::parse(text, nullptr, true, /*ignore_comments=*/true);
  } catch (const json::parse_error& error) {
    throw InvalidInput(source + ": malformed JSON: " + error.what());
  }
  ObjectReader scene(document, "", source);
  scene.allow_only({"material", "chain", "strikers", "wall", "contact", "impact", "record",
                    "method", "compliant", "precompression"});
  ChainScene result;
  std::optional<Material> fallback;
  if (scene.has("material")) fallback = read_material(scene, "material", source);

  ObjectReader chain(scene.at("chain"), "chain", source);
  chain.allow_only({"segments"});
  const json& segments = chain.at("segments");
  if (!segments.is_array() || segments.empty())
    chain.fail("chain.segments must be a non-empty array of segments");
  for (std::size_t k = 0; k < segments.size(); ++k)
    result.segments.push_back(
        read_segment(segments[k], "chain.segments[" + std::to_string(k) + "]", fallback, source));

  const json& strikers = scene.at("strikers");
  if (!strikers.is_array() || strikers.empty() || strikers.size() > 2)
    scene.fail("strikers must be an array of one or two strikers");
  for (std::size_t k = 0; k < strikers.size(); ++k)
    result.strikers.push_back(
        read_striker(strikers[k], "strikers[" + std::to_string(k) + "]", fallback, source));
  if (result.strikers.size() == 2 && result.strikers[0].side == result.strikers[1].side)
    scene.fail("strikers[0] and strikers[1] are both on the same side; allowed: one striker "
               "per side");

  if (scene.has("wall")) {
    ObjectReader wall(scene.at("wall"), "wall", source);
    wall.allow_only({"material"});
    result.wall = WallSpec{material_of(wall, fallback, source)};
    if (result.striker(Side::right))
      scene.fail("a right striker and a wall: the wall touches the last bead on the right; "
                 "allowed: one of them");
  }

  result.contact = read_contact(scene, source);
  read_impact(scene, source, result);
  read_record(scene, source, result);
  read_method(scene, source, result);
  read_precompression(scene, result);
  return result;
}

int ChainScene::bead_count() const {
  int count = 0;
  for (const SegmentSpec& segment : segments) count += segment.count;
  return count;
}

const StrikerSpec* ChainScene::striker(Side side) const {
  for (const StrikerSpec& striker : strikers)
    if (striker.side == side) return &striker;
  return nullptr;
}

numerics::LzbOptions ChainScene::lzb_options(double impulse_step) const {
  numerics::LzbOptions options;
  options.delta_p = impulse_step;
  options.fixed_thresholds = fixed_thresholds;
  return options;
}

ChainScene load_chain_scene(const std::filesystem::path& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    throw InvalidInput(path.string() + ": is a directory; allowed: a scene file (JSON)");
  std::ifstream in(path);
  if (!in) throw InvalidInput(path.string() + ": cannot open the scene file for reading");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_chain_scene(text.str(), path.string());
}

}  // namespace mimpact::chain
