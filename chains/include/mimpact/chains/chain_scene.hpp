#pragma once

#include <array>
#include <filesystem>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mimpact/chains/contact_model.hpp"
#include "mimpact/chains/hertz.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/common/fields.hpp"
#include "mimpact/kernel/json_document.hpp"
#include "mimpact/kernel/parameters.hpp"
#include "mimpact/numerics/contact_law.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"
#include "mimpact/plugins/lzb_impact_options.hpp"

// The chain scene file, docs/scenes.md. Every struct lists its fields once (visit_fields):
// the keys of the file, their checks and the messages about them.
namespace mimpact::chains {

// A run of beads; bead k+1 has radius (1 - taper) times bead k's.
struct SegmentSpec {
  int count = 0;
  double radius = 0.0;  // m, of the segment's first bead
  double taper = 0.0;   // in [0, 1)
  Material material;    // the scene's "material" when the segment gives none

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    // a bound on the count, so that a typo does not ask for 1e12 beads of memory
    field("count", self.count, within(1, 1e8).described("an integer >= 1, at most 1e8").needed());
    field("radius", self.radius, positive("m").needed());
    field("taper", self.taper, within(0.0, 1.0, {}, false, true).described("0 <= taper < 1"));
    field("material", self.material, any().needed());
  }
};

enum class Side { left, right };
constexpr auto enum_names(Side) {
  using Name = std::pair<Side, std::string_view>;
  return std::array{Name{Side::left, "left"}, Name{Side::right, "right"}};
}

// A striker's speed (m/s): below 1e-100 the impact's energies m v^2 / 2 fall under double
// precision's smallest numbers and the striker would count as at rest.
inline constexpr Allowed kStrikerSpeed =
    at_least(1e-100, "m/s, towards the chain; below, m v^2 underflows double precision");

// A bead thrown at one end of the chain.
struct StrikerSpec {
  Side side = Side::left;
  double radius = 0.0;    // m
  double velocity = 0.0;  // m/s towards the chain, > 0
  double gap = 0.0;       // m between the striker and the end bead, >= 0
  Material material;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("side", self.side);
    field("radius", self.radius, positive("m").needed());
    field("velocity", self.velocity, kStrikerSpeed.needed());
    field("gap", self.gap, at_least(0.0, "m"));
    field("material", self.material, any().needed());
  }
};

// A rigid immovable wall touching the last bead on the right.
struct WallSpec {
  Material material;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("material", self.material, any().needed());
  }
};

// What `mimpact chain --out` writes as time series: the force of these contacts and the
// velocity of these bodies, every `every` impulse steps.
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
// integrated in time (its reference for e = 1; the only one for a precompressed chain).
enum class Method { lzb, compliant };
constexpr auto enum_names(Method) {
  using Name = std::pair<Method, std::string_view>;
  return std::array{Name{Method::lzb, "lzb"}, Name{Method::compliant, "compliant"}};
}

// What a contact that opens during the impact does when its bodies approach again: close its
// gap first ("open", real beads), or close from where it stopped separating ("frozen", the
// LZB impact's frozen configuration; docs/model.md, section 13).
enum class Gaps { open, frozen };
constexpr auto enum_names(Gaps) {
  using Name = std::pair<Gaps, std::string_view>;
  return std::array{Name{Gaps::open, "open"}, Name{Gaps::frozen, "frozen"}};
}

struct CompliantSpec {
  double tolerance = 1e-10;        // relative error control of the integration
  std::optional<double> end_time;  // s; required with a precompression
  Gaps gaps = Gaps::open;
  std::int64_t max_steps = 10'000'000;  // time steps before the run is abandoned

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    // below 1e-14 the error estimate of Dormand-Prince drowns in round-off: the run never ends
    field("tolerance", self.tolerance,
          within(1e-14, 1.0, {}, false, true).described("1e-14 <= tolerance < 1"));
    field("end_time", self.end_time, positive("s"));
    field("gaps", self.gaps);
    field("max_steps", self.max_steps, at_least(1, "time steps"));
  }
};

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

struct ContactSpec {
  numerics::ComplianceModel model = numerics::ComplianceModel::bi_stiffness;
  double exponent = 1.5;
  double restitution = 1.0;
  // K (N/m^eta) of every contact; when absent, Hertz's, which needs exponent 3/2
  std::optional<double> stiffness;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("model", self.model);
    // past 10, K delta^eta overflows for overlaps of a few radii
    field("exponent", self.exponent,
          within(0.0, 10.0, "1 linear, 3/2 Hertz", true).described("0 < eta <= 10"));
    field("restitution", self.restitution, within(0.0, 1.0).described("0 <= e <= 1"));
    field("stiffness", self.stiffness, positive("N/m^exponent"));
  }

  // Hertz's stiffness needs exponent 3/2: another exponent needs its stiffness.
  void check(const SceneChecks& checks) const;
  // The law of a contact whose Hertz stiffness is `hertz` (N/m^1.5): K the scene's, or Hertz's.
  numerics::ContactLaw law(double hertz) const {
    return {.stiffness = stiffness.value_or(hertz),
            .exponent = exponent,
            .restitution = restitution,
            .model = model};
  }
};

struct ChainSpec {
  std::vector<SegmentSpec> segments;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("segments", self.segments, any().needed());
  }
};

// A chain scene file (the format: docs/scenes.md). Bodies are numbered left to right: a
// left striker, the beads, a right striker; contact i joins bodies i and i + 1, and the
// wall's contact, if any, comes last.
struct ChainScene {
  std::optional<Material> material;  // of the beads, strikers and wall that name none
  ChainSpec chain;
  std::vector<StrikerSpec> strikers;  // one or two, on different sides
  std::optional<WallSpec> wall;
  ContactSpec contact;
  // "impact": the options of the "lzb" impact problem; resolve_impact() merges what the command
  // line or Python chose over them
  plugins::LzbImpactOptions impact;
  RecordSpec record;
  Method method = Method::lzb;
  CompliantSpec compliant;
  // N: a constant force on the first bead pushes the chain against its wall (compliant only)
  double precompression = 0.0;
  std::string source = "scene";  // the file it was read from, for messages

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("material", self.material);
    field("chain", self.chain, any().needed());
    field("strikers", self.strikers, any().needed());
    field("wall", self.wall);
    field("contact", self.contact);
    field("impact", self.impact);
    field("record", self.record);
    field("method", self.method);
    field("compliant", self.compliant);
    field("precompression", self.precompression, at_least(0.0, "N"));
  }

  int bead_count() const;
  int body_count() const { return bead_count() + int(strikers.size()); }
  int contact_count() const { return body_count() - 1 + (wall ? 1 : 0); }
  const StrikerSpec* striker(Side side) const;
  // The LZB method with "integrator": "adaptive" (a tolerance, no delta_p).
  bool adaptive() const {
    return method == Method::lzb && impact.integrator == plugins::LzbIntegrator::adaptive;
  }
};

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
  std::optional<double> delta_p;         // N s
  std::string delta_p_name = "delta_p";  // what messages call it: "--delta-p"
};

// The scene's impact options with the overrides, checked by the one rule of the impact options
// (plugins::LzbImpactOptions::check) for the LZB method; an override given to the compliant
// method is refused. Throws InvalidInput naming `source` and each field where it was given.
plugins::LzbImpactOptions resolve_impact(const plugins::LzbImpactOptions& impact, Method method,
                                         const ImpactOverrides& overrides,
                                         const std::string& source);
// What messages call the impact options' fields, given the overrides.
fields::Labels impact_labels(const ImpactOverrides& overrides);

// The impulse steps' delta_p (N s) for the checks before a run: the options' delta_p, or
// relative_delta_p times the natural impulse of the model's contacts; checked against the model
// (check_delta_p, naming the field as `labels` does). InvalidInput when there is neither.
double impulse_step(const ContactModel& model, const plugins::LzbImpactOptions& impact,
                    const fields::Labels& labels);

// Reads a scene document (its keys as docs/scenes.md lists them). Throws InvalidInput naming
// the source, the field (and its line and column when `locations` are given), its value and
// what is allowed; unknown keys are errors.
ChainScene read_chain_scene(nlohmann::json document, const std::string& source,
                            const kernel::JsonLocations* locations = nullptr);
// Parses and reads a scene (JSON, comments allowed).
ChainScene parse_chain_scene(std::string_view text, const std::string& source);
ChainScene load_chain_scene(const std::filesystem::path& path);
// A scene file's text; InvalidInput when it is not a regular file, is larger than 64 MB or
// cannot be read.
std::string read_scene_file(const std::filesystem::path& path);

}  // namespace mimpact::chains
