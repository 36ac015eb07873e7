#include "mimpact/granular/scene_spec.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

namespace mimpact::granular {

namespace {

using nlohmann::json;

// larger than any scene needs: the text is held in memory while it is parsed
constexpr std::uintmax_t kLargestSceneFile = 64u << 20;

}  // namespace

void CompliantSpec::check_tolerance(bool moving, const SceneChecks& checks) const {
  if (moving || tolerance <= kLoosestFrozenTolerance) return;
  checks.fail("compliant.tolerance = " + to_text(tolerance) +
              " is invalid where the frozen geometry integrates (a chain, or compliant.geometry "
              "\"frozen\"); allowed: 1e-14 <= tolerance <= 1e-4 (up to 1e-1 in a packing's "
              "moving geometry)");
}

void check_compliant_restitution(const ContactSpec& contact, const SceneChecks& checks) {
  if (contact.restitution >= kLeastCompliantRestitution) return;
  checks.fail("contact.restitution = " + to_text(contact.restitution) +
              " with \"method\": \"compliant\"; allowed: restitution >= " +
              to_text(kLeastCompliantRestitution) +
              " (below it the compliant outcome does not converge with the tolerance, and near 0 "
              "touching beads collide again and again; the LZB method takes any restitution)");
}

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
  for (std::size_t k = 0; k < pairs.size(); ++k)
    if (pairs[k].materials.size() != 2)
      checks.fail("contact.pairs[" + std::to_string(k) + "].materials has " +
                  std::to_string(pairs[k].materials.size()) +
                  " names; allowed: two material names (the same twice for a material with "
                  "itself)");
}

void ContactSpec::check_pairs(const std::vector<std::string>& names,
                              const SceneChecks& checks) const {
  for (std::size_t k = 0; k < pairs.size(); ++k)
    for (std::size_t i = 0; i < 2; ++i)
      if (std::find(names.begin(), names.end(), pairs[k].materials[i]) == names.end()) {
        std::string known;
        for (const std::string& name : names) known += (known.empty() ? "" : ", ") + name;
        checks.fail("contact.pairs[" + std::to_string(k) + "].materials[" + std::to_string(i) +
                    "] = \"" + pairs[k].materials[i] +
                    "\" names no material of the scene; allowed: " +
                    (known.empty() ? "a material's \"name\"" : known));
      }
}

fields::Labels impact_labels(const ImpactOverrides& overrides) {
  fields::Labels labels{.prefix = "impact."};
  if (overrides.delta_p) labels.chosen.emplace_back("delta_p", overrides.delta_p_name);
  return labels;
}

void check_accuracy_alone(const nlohmann::json& document, const SceneChecks& checks) {
  if (!document.is_object() || !document.contains("accuracy") || document["accuracy"].is_null())
    return;
  for (const char* pointer : {"/impact/delta_p", "/impact/relative_delta_p", "/impact/tolerance",
                              "/compliant/tolerance"}) {
    const json::json_pointer field(pointer);
    if (!document.contains(field)) continue;
    std::string name = pointer + 1;
    std::replace(name.begin(), name.end(), '/', '.');
    checks.fail(name + " = " + document.at(field).dump() +
                " beside accuracy = " + document.at("accuracy").dump() +
                ": the accuracy chooses the step; allowed: one of them");
  }
}

std::optional<double> resolve_accuracy(std::optional<double> scene_accuracy,
                                       const ImpactOverrides& overrides) {
  if (overrides.delta_p && overrides.accuracy)
    throw InvalidInput(overrides.delta_p_name + " = " + to_text(*overrides.delta_p) + " beside " +
                       overrides.accuracy_name + " = " + to_text(*overrides.accuracy) +
                       ": the accuracy chooses delta_p; allowed: one of them");
  if (overrides.accuracy) {
    fields::Validator("", "").check(overrides.accuracy_name, *overrides.accuracy, kAccuracyRange);
    return overrides.accuracy;
  }
  return overrides.delta_p ? std::nullopt : scene_accuracy;
}

plugins::LzbImpactOptions resolve_impact(const plugins::LzbImpactOptions& impact, Method method,
                                         const ImpactOverrides& overrides,
                                         const std::string& source,
                                         std::optional<double> accuracy) {
  plugins::LzbImpactOptions resolved = impact;
  if (overrides.delta_p) resolved.delta_p = overrides.delta_p;
  if (accuracy) {
    resolved.delta_p.reset();
    resolved.relative_delta_p.reset();
    resolved.tolerance.reset();
    if (!resolved.integrator) resolved.integrator = plugins::LzbIntegrator::adaptive;
  }
  const fields::Labels labels = impact_labels(overrides);
  // a scene keeps its LZB options beside the compliant ones ("method" picks), but a step asked
  // of a compliant run is an error
  if (method == Method::compliant && overrides.delta_p)
    throw InvalidInput(overrides.delta_p_name + " = " + to_text(*overrides.delta_p) +
                       " is the step of the LZB method; " + source +
                       " has method \"compliant\" (its accuracy is compliant.tolerance)");
  if (method == Method::compliant) return resolved;
  resolved.check(source, labels);
  return resolved;
}

double impulse_step(const ContactModel& model, const plugins::LzbImpactOptions& impact,
                    const fields::Labels& labels) {
  if (!impact.delta_p && !impact.relative_delta_p)
    throw InvalidInput(
        "missing field impact.delta_p (the impulse steps' principal step, N s), or "
        "impact.relative_delta_p; or choose \"integrator\": \"adaptive\" with a tolerance");
  if (impact.delta_p) {
    check_delta_p(model, *impact.delta_p, impact.impulse_steps.max_steps, labels("delta_p"));
    return *impact.delta_p;
  }
  const double delta_p = *impact.relative_delta_p * natural_impulse(model);
  check_delta_p(model, delta_p, impact.impulse_steps.max_steps,
                labels("relative_delta_p") + " x the natural impulse");
  return delta_p;
}

kernel::JsonDocument parse_scene_document(std::string_view text, const std::string& source) {
  return kernel::parse_json_document(text, source);
}

std::string read_scene_file(const std::filesystem::path& path) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (std::filesystem::is_directory(status))
    throw InvalidInput(path.string() + ": is a directory; allowed: a scene file (JSON)");
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
    throw InvalidInput(path.string() +
                       ": is not a regular file (a device or a pipe); allowed: a scene file");
  const auto size = std::filesystem::file_size(path, error);
  if (!error && size > kLargestSceneFile)
    throw InvalidInput(path.string() + ": holds " + std::to_string(size) +
                       " bytes; allowed: a scene file of at most 64 MB (bead lists belong in "
                       "CSV files)");
  std::ifstream in(path);
  if (!in) throw InvalidInput(path.string() + ": cannot open the scene file for reading");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace mimpact::granular
