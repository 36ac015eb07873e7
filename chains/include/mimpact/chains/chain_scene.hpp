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
#include "mimpact/kernel/parameters.hpp"
#include "mimpact/numerics/contact_law.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"

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
    field("velocity", self.velocity, positive("m/s, towards the chain").needed());
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

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    // below 1e-14 the error estimate of Dormand-Prince drowns in round-off: the run never ends
    field("tolerance", self.tolerance,
          within(1e-14, 1.0, {}, false, true).described("1e-14 <= tolerance < 1"));
    field("end_time", self.end_time, positive("s"));
    field("gaps", self.gaps);
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
  // "impact": the parameters of the "lzb" impact problem (plugins::LzbImpactOptions), but
  // delta_p, which is apart because the command line may choose it
  kernel::Parameters impact = kernel::Parameters::object();
  std::optional<double> delta_p;  // N s, from "impact": {"delta_p"}
  RecordSpec record;
  Method method = Method::lzb;
  CompliantSpec compliant;
  // N: a constant force on the first bead pushes the chain against its wall (compliant only)
  double precompression = 0.0;

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
  // The "lzb" impact problem's options as the scene gives them (delta_p its own, or the
  // default), and the LZB integrator's among them at delta_p = impulse_step (N s).
  plugins::LzbImpactOptions impact_options() const;
  // The LZB method with "integrator": "adaptive" (a tolerance, no delta_p).
  bool adaptive() const;
  numerics::LzbOptions lzb_options(double impulse_step) const;
};

// A scene file's JSON (comments allowed); InvalidInput "SOURCE: malformed JSON: ..." otherwise.
nlohmann::json parse_scene_document(std::string_view text, const std::string& source);

// Copies the top-level "material" of a scene document into every body that names none, so
// that one field list reads every body alike. `bodies` are JSON pointers to a body or an array
// of bodies ("/chain/segments"); throws InvalidInput naming the body when it needs the
// top-level material and there is none.
void lend_material(nlohmann::json& document, std::initializer_list<const char*> bodies,
                   const std::string& source);

// Reads "impact" as the "lzb" impact problem reads its parameters (InvalidInput naming `source`
// on a bad one) and takes delta_p out of it: the command line may choose it instead.
std::optional<double> take_delta_p(kernel::Parameters& impact, const std::string& source);
// The impulse steps' delta_p (N s): `chosen` (the command line's) or else the scene's, checked
// against the model (check_delta_p, naming `field`); InvalidInput when there is none.
double impulse_step(const ContactModel& model, std::optional<double> chosen,
                    std::optional<double> scene_value, std::int64_t max_steps,
                    const std::string& field);
// The "lzb" impact problem's options of "impact", with delta_p when given.
plugins::LzbImpactOptions lzb_impact_options(const kernel::Parameters& impact,
                                             std::optional<double> delta_p);

// Parses and validates a scene (JSON, comments allowed). Throws InvalidInput naming the
// source, the field, its value and what is allowed; unknown keys are errors.
ChainScene parse_chain_scene(std::string_view text, const std::string& source);
ChainScene load_chain_scene(const std::filesystem::path& path);
// A scene file's text; InvalidInput when it is a directory or cannot be read.
std::string read_scene_file(const std::filesystem::path& path);

}  // namespace mimpact::chains
