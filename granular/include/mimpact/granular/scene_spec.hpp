#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mimpact/common/error.hpp"
#include "mimpact/common/fields.hpp"
#include "mimpact/granular/contact_model.hpp"
#include "mimpact/granular/hertz.hpp"
#include "mimpact/kernel/json_document.hpp"
#include "mimpact/numerics/contact_law.hpp"
#include "mimpact/plugins/lzb_impact_options.hpp"

// What every granular scene file holds beside its geometry (docs/scenes.md, docs/packings.md):
// the contact law, the method and its options, what is recorded, and the reading of the file.
// Every struct lists its fields once (visit_fields): the keys of the file, their checks and the
// messages about them.
namespace mimpact::granular {

// The slowest striker (m/s): below 1e-100 the impact's energies m v^2 / 2 fall under double
// precision's smallest numbers and the striker would count as at rest.
inline constexpr double kSlowestStriker = 1e-100;

// What a run records as time series: the force of these contacts and the velocity of these
// bodies, every `every` impulse steps or every `interval` seconds.
struct RecordSpec {
  std::vector<int> contacts;
  std::vector<int> bodies;
  int every = 1;           // LZB impulse steps: one sample every this many steps
  double interval = 1e-7;  // compliant and adaptive LZB: one sample every this long (s)

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("contacts", self.contacts, at_least(0));
    field("bodies", self.bodies, at_least(0));
    field("every", self.every, at_least(1, "impulse steps"));
    field("interval", self.interval, positive("s"));
  }
};

// How the impact is computed: the LZB impulse dynamics (the default) or the compliant contacts
// integrated in time (its reference for e = 1; the only one for a precompressed chain), or the
// cheaper of the two that the scene's configuration lets meet its accuracy ("auto",
// granular::run_scene).
enum class Method { lzb, compliant, automatic };
constexpr auto enum_names(Method) {
  using Name = std::pair<Method, std::string_view>;
  return std::array{Name{Method::lzb, "lzb"}, Name{Method::compliant, "compliant"},
                    Name{Method::automatic, "auto"}};
}

// What a contact that opens during the impact does when its bodies approach again: close its
// gap first ("open", real beads), or close from where it stopped separating ("frozen", the
// LZB impact's frozen configuration; docs/model.md, section 13).
enum class Gaps { open, frozen };
constexpr auto enum_names(Gaps) {
  using Name = std::pair<Gaps, std::string_view>;
  return std::array{Name{Gaps::open, "open"}, Name{Gaps::frozen, "frozen"}};
}

// Where the compliant contacts are: at the configuration of the impact, LZB's own assumption
// (gaps along frozen normals), or where the bodies are now (docs/model.md, section 17). A
// chain's gaps are linear: both are the same there.
enum class Geometry { moving, frozen };
constexpr auto enum_names(Geometry) {
  using Name = std::pair<Geometry, std::string_view>;
  return std::array{Name{Geometry::moving, "moving"}, Name{Geometry::frozen, "frozen"}};
}

// Throws InvalidInput naming the scene file: "SOURCE: what".
class SceneChecks {
 public:
  explicit SceneChecks(const std::string& source) : source_(source) {}
  [[noreturn]] void fail(const std::string& what) const {
    throw InvalidInput(source_ + ": " + what);
  }

 private:
  const std::string& source_;
};

struct CompliantSpec {
  double tolerance = 1e-10;        // relative error control of the integration
  std::optional<double> end_time;  // s; required with a precompression
  Gaps gaps = Gaps::open;
  Geometry geometry = Geometry::moving;
  // time steps (and the moving geometry's windows) before the run is abandoned
  std::int64_t max_steps = 10'000'000;
  // not a scene field: a caller's budget of work in the moving geometry (MovingContactsOptions)
  std::int64_t max_body_steps = std::numeric_limits<std::int64_t>::max();

  // The loosest tolerance where the frozen geometry integrates (a chain, or compliant.geometry
  // "frozen"): above it the frozen integrator leaves out overlaps below 10 tolerance^(2 / (1 +
  // eta)) of the impact's, a departure from the law rather than an integration error. The moving
  // geometry resolves overlaps down to (1e-2 tolerance)^(1 / eta) of the impact's and takes up
  // to 1e-1 (docs/design/moving_geometry.md, "One tolerance").
  static constexpr double kLoosestFrozenTolerance = 1e-4;
  // The loosest tolerance of all (the moving geometry's).
  static constexpr double kLoosestTolerance = 1e-1;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    // below 1e-14 the error estimates drown in round-off: the run never ends
    field("tolerance", self.tolerance,
          within(1e-14, kLoosestTolerance).described("1e-14 <= tolerance <= 1e-1"));
    field("end_time", self.end_time, positive("s"));
    field("gaps", self.gaps);
    field("geometry", self.geometry);
    field("max_steps", self.max_steps, at_least(1, "time steps"));
  }
  // The tolerance against the geometry that integrates it: `moving` where the beads' own
  // positions set the contacts (a packing in the moving geometry).
  void check_tolerance(bool moving, const SceneChecks& checks) const;
};

// Coulomb's mu of the contacts between two named materials (Material::name), in either order.
struct FrictionPair {
  std::vector<std::string> materials;
  double friction = 0.0;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("materials", self.materials, any("two material names").needed());
    field("friction", self.friction, at_least(0.0, "Coulomb's mu").needed());
  }
};

struct ContactSpec {
  numerics::ComplianceModel model = numerics::ComplianceModel::bi_stiffness;
  double exponent = 1.5;
  double restitution = 1.0;
  // K (N/m^eta) of every contact; when absent, Hertz's, which needs exponent 3/2
  std::optional<double> stiffness;
  double friction = 0.0;            // Coulomb's mu of every contact (docs/model.md, section 16)
  std::vector<FrictionPair> pairs;  // mu per pair of materials, over `friction`

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("model", self.model);
    // past 10, K delta^eta overflows for overlaps of a few radii
    field("exponent", self.exponent,
          within(0.0, 10.0, "1 linear, 3/2 Hertz", true).described("0 < eta <= 10"));
    field("restitution", self.restitution, within(0.0, 1.0).described("0 <= e <= 1"));
    field("stiffness", self.stiffness, positive("N/m^exponent"));
    field("friction", self.friction, at_least(0.0, "Coulomb's mu; 0: frictionless"));
    field("pairs", self.pairs);
  }
  // mu of a contact of materials a and b: the last pair naming both, else `friction`
  double friction_of(const Material& a, const Material& b) const {
    double mu = friction;
    for (const FrictionPair& pair : pairs)
      if ((pair.materials[0] == a.name && pair.materials[1] == b.name) ||
          (pair.materials[0] == b.name && pair.materials[1] == a.name))
        mu = pair.friction;
    return mu;
  }

  // Hertz's stiffness needs exponent 3/2: another exponent needs its stiffness; a pair names two
  // materials.
  void check(const SceneChecks& checks) const;
  // Every pair's names are among `names` (the scene's named materials).
  void check_pairs(const std::vector<std::string>& names, const SceneChecks& checks) const;
  // The law of a contact whose Hertz stiffness is `hertz` (N/m^1.5): K the scene's, or Hertz's.
  numerics::ContactLaw law(double hertz) const {
    return {.stiffness = stiffness.value_or(hertz),
            .exponent = exponent,
            .restitution = restitution,
            .model = model,
            .friction = friction};
  }
};

// The least restitution of a scene's compliant contacts, in chains and packings: below it their
// outcome does not converge with the tolerance (in packings it is ill-conditioned in the scene's
// data), and as e -> 0 touching beads collide again and again, at a cost growing as 1/e under a
// load; the LZB method takes any e (docs/limits.md, "Small restitution").
inline constexpr double kLeastCompliantRestitution = 0.2;
// Refuses compliant contacts below kLeastCompliantRestitution, naming contact.restitution.
void check_compliant_restitution(const ContactSpec& contact, const SceneChecks& checks);

// A scene file's JSON: parse_json_document's limits, and its messages naming the file, line,
// column and field.
kernel::JsonDocument parse_scene_document(std::string_view text, const std::string& source);

// Copies the top-level "material" of a scene document into every body that names none, so
// that one field list reads every body alike. `bodies` are JSON pointers to a body or an array
// of bodies ("/chain/segments"); throws InvalidInput naming the body when it needs the
// top-level material and there is none.
void lend_material(nlohmann::json& document, std::initializer_list<const char*> bodies,
                   const std::string& source);

// What a caller may choose over a scene's "impact": the command line's --delta-p, Python's
// delta_p=.
struct ImpactOverrides {
  std::optional<double> delta_p;           // N s
  std::string delta_p_name = "delta_p";    // what messages call it: "--delta-p"
  std::optional<double> accuracy;          // over the scene's step rule and its "accuracy"
  std::string accuracy_name = "accuracy";  // "--accuracy"
};

// A scene's "accuracy": the error asked of the answer, a share of the fastest speed before the
// impact, for its worst body (ErrorEstimate::worst); the run chooses its step to meet it.
inline constexpr Allowed kAccuracyRange =
    within(1e-12, 0.1).described("1e-12 <= accuracy <= 0.1 (of the fastest speed before impact)");

// Refuses a step rule beside a scene document's "accuracy" (impact.delta_p, relative_delta_p,
// tolerance, compliant.tolerance): the accuracy chooses the step.
void check_accuracy_alone(const nlohmann::json& document, const SceneChecks& checks);

// The accuracy a run is asked for: the caller's, else the scene's unless the caller chose a
// delta_p. Throws InvalidInput naming both when the caller gave both, and the caller's accuracy
// out of kAccuracyRange.
std::optional<double> resolve_accuracy(std::optional<double> scene_accuracy,
                                       const ImpactOverrides& overrides);

// The scene's impact options with the overrides, checked by the one rule of the impact options
// (plugins::LzbImpactOptions::check) for the LZB method; an override given to the compliant
// method is refused. Throws InvalidInput naming `source` and each field where it was given. Asked
// for an `accuracy` (resolve_accuracy), the step fields are left to the run, and an LZB run with
// no integrator named takes the adaptive one.
plugins::LzbImpactOptions resolve_impact(const plugins::LzbImpactOptions& impact, Method method,
                                         const ImpactOverrides& overrides,
                                         const std::string& source,
                                         std::optional<double> accuracy = {});
// What messages call the impact options' fields, given the overrides.
fields::Labels impact_labels(const ImpactOverrides& overrides);

// The impulse steps' delta_p (N s) for the checks before a run: the options' delta_p, or
// relative_delta_p times the natural impulse of the model's contacts; checked against the model
// (check_delta_p, naming the field as `labels` does). InvalidInput when there is neither.
double impulse_step(const ContactModel& model, const plugins::LzbImpactOptions& impact,
                    const fields::Labels& labels);

// A scene file's text; InvalidInput when it is not a regular file, is larger than 64 MB or
// cannot be read.
std::string read_scene_file(const std::filesystem::path& path);

}  // namespace mimpact::granular
