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

#include "mimpact/common/error.hpp"
#include "mimpact/common/fields.hpp"
#include "mimpact/granular/hertz.hpp"
#include "mimpact/granular/scene_spec.hpp"
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
  double radius = 0.0;          // m, of the segment's first bead
  double taper = 0.0;           // in [0, 1)
  granular::Material material;  // the scene's "material" when the segment gives none

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

// A striker's speed (m/s), at least granular::kSlowestStriker.
inline constexpr Allowed kStrikerSpeed = at_least(
    granular::kSlowestStriker, "m/s, towards the chain; below, m v^2 underflows double precision");

// A bead thrown at one end of the chain.
struct StrikerSpec {
  Side side = Side::left;
  double radius = 0.0;    // m
  double velocity = 0.0;  // m/s towards the chain, > 0
  double gap = 0.0;       // m between the striker and the end bead, >= 0
  granular::Material material;

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
  granular::Material material;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("material", self.material, any().needed());
  }
};

// One bead of a chain given bead by bead (a dimer chain: alternating radii).
struct BeadSpec {
  double radius = 0.0;          // m
  granular::Material material;  // the scene's "material" when the bead gives none

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("radius", self.radius, positive("m").needed());
    field("material", self.material, any().needed());
  }
};

// The beads, left to right: runs of beads (segments), or the beads one by one.
struct ChainSpec {
  std::vector<SegmentSpec> segments;
  std::vector<BeadSpec> beads;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("segments", self.segments);
    field("beads", self.beads);
  }
  // "chain.segments" or "chain.beads", for messages
  std::string key() const { return beads.empty() ? "chain.segments" : "chain.beads"; }
};

// A chain scene file (the format: docs/scenes.md). Bodies are numbered left to right: a
// left striker, the beads, a right striker; contact i joins bodies i and i + 1, and the
// wall's contact, if any, comes last.
struct ChainScene {
  std::optional<granular::Material> material;  // of the beads, strikers and wall that name none
  ChainSpec chain;
  std::vector<StrikerSpec> strikers;  // one or two, on different sides
  std::optional<WallSpec> wall;
  granular::ContactSpec contact;
  // "impact": the options of the "lzb" impact problem; resolve_impact() merges what the command
  // line or Python chose over them
  plugins::LzbImpactOptions impact;
  granular::RecordSpec record;
  granular::Method method = granular::Method::lzb;
  granular::CompliantSpec compliant;
  // the error asked of the answer (granular::kAccuracyRange): the run chooses its step
  std::optional<double> accuracy;
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
    field("accuracy", self.accuracy, granular::kAccuracyRange);
  }

  int bead_count() const;
  int body_count() const { return bead_count() + int(strikers.size()); }
  int contact_count() const { return body_count() - 1 + (wall ? 1 : 0); }
  const StrikerSpec* striker(Side side) const;
  // The LZB method with "integrator": "adaptive" (a tolerance, no delta_p).
  bool adaptive() const {
    return method == granular::Method::lzb && impact.integrator == plugins::LzbIntegrator::adaptive;
  }
};

// Reads a scene document (its keys as docs/scenes.md lists them). Throws InvalidInput naming
// the source, the field (and its line and column when `locations` are given), its value and
// what is allowed; unknown keys are errors.
ChainScene read_chain_scene(nlohmann::json document, const std::string& source,
                            const kernel::JsonLocations* locations = nullptr);
// Parses and reads a scene (JSON, comments allowed).
ChainScene parse_chain_scene(std::string_view text, const std::string& source);
ChainScene load_chain_scene(const std::filesystem::path& path);
}  // namespace mimpact::chains
