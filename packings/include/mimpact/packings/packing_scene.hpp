#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mimpact/common/fields.hpp"
#include "mimpact/granular/hertz.hpp"
#include "mimpact/granular/scene_spec.hpp"
#include "mimpact/kernel/parameters.hpp"
#include "mimpact/plugins/lzb_impact_options.hpp"

// The planar packing scene file, docs/scenes.md ("Planar packings"). Like the chain scenes,
// every struct lists its fields once (visit_fields): the keys, their checks and the messages.
namespace mimpact::packings {

enum class LatticeType { square, hexagonal };
constexpr auto enum_names(LatticeType) {
  using Name = std::pair<LatticeType, std::string_view>;
  return std::array{Name{LatticeType::square, "square"}, Name{LatticeType::hexagonal, "hexagonal"}};
}

// Equal beads touching on a lattice: rows along x, row 0 at the bottom; bead (row r, column c)
// is number r * columns + c. Square: centre (2a c, 2a r). Hexagonal: centre
// (2a c + a (r mod 2), sqrt(3) a r), odd rows shifted by a.
struct LatticeSpec {
  LatticeType type = LatticeType::square;
  int rows = 0;
  int columns = 0;
  double radius = 0.0;          // a (m)
  granular::Material material;  // the scene's "material" when the lattice gives none

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("type", self.type);
    // a bound on the count, so that a typo does not ask for 1e12 beads of memory
    field("rows", self.rows, within(1, 1e7).described("an integer >= 1, at most 1e7").needed());
    field("columns", self.columns,
          within(1, 1e7).described("an integer >= 1, at most 1e7").needed());
    field("radius", self.radius, positive("m").needed());
    field("material", self.material, any().needed());
  }
};

// Beads listed in a CSV file: a header "x,y,radius" (m), then one bead per line, numbered in
// the file's order.
struct BeadListSpec {
  std::string file;  // relative to the scene file's directory
  granular::Material material;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("file", self.file, any("a CSV file with columns x,y,radius").needed());
    field("material", self.material, any().needed());
  }
};

enum class WallSide { bottom, top, left, right };
constexpr auto enum_names(WallSide) {
  using Name = std::pair<WallSide, std::string_view>;
  return std::array{Name{WallSide::bottom, "bottom"}, Name{WallSide::top, "top"},
                    Name{WallSide::left, "left"}, Name{WallSide::right, "right"}};
}

// A rigid straight wall: on one side of the packing, touching its outermost beads, or the line
// through `point` whose `normal` points to the beads' side.
struct WallSpec {
  std::optional<WallSide> side;
  std::vector<double> point;   // m, [x, y]
  std::vector<double> normal;  // [nx, ny], normalized when read
  granular::Material material;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("side", self.side);
    field("point", self.point, any("m"));
    field("normal", self.normal);
    field("material", self.material, any().needed());
  }
};

// A bead thrown at a bead of the packing, placed against its target on the side it comes
// from (gap away along its velocity).
struct StrikerSpec {
  // [row, column] in a lattice, [bead] in a bead list
  std::vector<int> target;
  double radius = 0.0;           // m
  std::vector<double> velocity;  // m/s, [vx, vy]
  double gap = 0.0;              // m between the striker and its target, >= 0
  granular::Material material;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("target", self.target, at_least(0, "[row, column], or [bead] in a bead list").needed());
    field("radius", self.radius, positive("m").needed());
    field("velocity", self.velocity, any("m/s, [vx, vy]").needed());
    field("gap", self.gap, at_least(0.0, "m"));
    field("material", self.material, any().needed());
  }
};

// What `mimpact packing --out` writes as time series: the force of these contacts and the
// velocity of these beads, every `every` impulse steps (or `interval` seconds); and, with
// `frames` = k > 0, every k-th sample a frame of the whole packing (frames.json, the ParaView
// files and the force-chain figures are drawn from them).
struct RecordSpec {
  std::vector<int> contacts;
  std::vector<int> beads;
  int every = 1;
  double interval = 1e-7;
  int frames = 0;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("contacts", self.contacts, at_least(0));
    field("beads", self.beads, at_least(0, "bodies: the packing's beads, then the strikers"));
    field("every", self.every, at_least(1, "impulse steps"));
    field("interval", self.interval, positive("s"));
    field("frames", self.frames, at_least(0, "a frame every this many samples; 0: none"));
  }
};

// A planar packing scene file. Bodies are the packing's beads (a lattice row by row, or the
// bead list's order), then the strikers.
struct PackingScene {
  std::optional<granular::Material> material;  // of the bodies and walls that name none
  std::optional<LatticeSpec> lattice;
  std::optional<BeadListSpec> beads;  // one of lattice and beads
  std::vector<WallSpec> walls;
  std::vector<StrikerSpec> strikers;
  granular::ContactSpec contact;
  // "impact": the options of the "lzb" impact problem (granular::resolve_impact merges what the
  // command line or Python chose over them)
  plugins::LzbImpactOptions impact;
  RecordSpec record;
  granular::Method method = granular::Method::lzb;
  granular::CompliantSpec compliant;
  std::filesystem::path directory;  // of the scene file: bead lists are found from it
  std::string source = "scene";     // the file it was read from, for messages

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("material", self.material);
    field("lattice", self.lattice);
    field("beads", self.beads);
    field("walls", self.walls);
    field("strikers", self.strikers, any().needed());
    field("contact", self.contact);
    field("impact", self.impact);
    field("record", self.record);
    field("method", self.method);
    field("compliant", self.compliant);
  }

  bool adaptive() const {
    return method == granular::Method::lzb && impact.integrator == plugins::LzbIntegrator::adaptive;
  }
  // what the run records (granular::run_scene): the beads as bodies
  granular::RecordSpec run_record() const;
};

// Reads a scene document; `directory` is where bead lists are looked for. Throws InvalidInput
// naming the source, the field (with its line and column when `locations` are given), its
// value and what is allowed; unknown keys are errors.
PackingScene read_packing_scene(nlohmann::json document, const std::string& source,
                                const std::filesystem::path& directory,
                                const kernel::JsonLocations* locations = nullptr);
// Parses and reads a scene (JSON, comments allowed).
PackingScene parse_packing_scene(std::string_view text, const std::string& source,
                                 const std::filesystem::path& directory = ".");
PackingScene load_packing_scene(const std::filesystem::path& path);

}  // namespace mimpact::packings
