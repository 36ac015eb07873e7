#pragma once

#include <Eigen/Dense>
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mimpact/common/fields.hpp"
#include "mimpact/granular/configuration_check.hpp"
#include "mimpact/granular/hertz.hpp"
#include "mimpact/granular/scene_spec.hpp"
#include "mimpact/kernel/parameters.hpp"
#include "mimpact/plugins/lzb_impact_options.hpp"

// The packing scene file, docs/scenes.md ("Packings"), in two or three dimensions. Like the chain
// scenes, every struct lists its fields once (visit_fields): the keys, their checks and the
// messages.
namespace mimpact::packings {

// A point or a direction of the packing's space: `dimension` components (2 or 3), on the stack.
using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, 3, 1>;

enum class LatticeType { square, hexagonal, simple_cubic, fcc, hcp };
constexpr auto enum_names(LatticeType) {
  using Name = std::pair<LatticeType, std::string_view>;
  return std::array{Name{LatticeType::square, "square"}, Name{LatticeType::hexagonal, "hexagonal"},
                    Name{LatticeType::simple_cubic, "simple-cubic"}, Name{LatticeType::fcc, "fcc"},
                    Name{LatticeType::hcp, "hcp"}};
}
// 2 for the planar lattices, 3 for the others.
constexpr int lattice_dimension(LatticeType type) {
  return type == LatticeType::square || type == LatticeType::hexagonal ? 2 : 3;
}

// Equal beads touching on a lattice: rows along x, row 0 at the bottom, layers along z; bead
// (layer l, row r, column c) is number (l rows + r) columns + c (l = 0 in the plane). Square:
// centre (2a c, 2a r). Hexagonal: (2a c + a (r mod 2), sqrt(3) a r), odd rows shifted by a.
// Simple cubic: (2a c, 2a r, 2a l). FCC and HCP: hexagonal layers 2 sqrt(2/3) a apart, each
// shifted by (a, a / sqrt(3)) from the one below, stacked ABCABC (FCC, its (111) planes) or
// ABAB (HCP).
struct LatticeSpec {
  LatticeType type = LatticeType::square;
  int layers = 0;  // three-dimensional lattices only
  int rows = 0;
  int columns = 0;
  double radius = 0.0;          // a (m)
  granular::Material material;  // the scene's "material" when the lattice gives none

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("type", self.type);
    // a bound on the count, so that a typo does not ask for 1e12 beads of memory
    field("layers", self.layers,
          within(1, 1e7).described("an integer >= 1, at most 1e7 (three-dimensional lattices)"));
    field("rows", self.rows, within(1, 1e7).described("an integer >= 1, at most 1e7").needed());
    field("columns", self.columns,
          within(1, 1e7).described("an integer >= 1, at most 1e7").needed());
    field("radius", self.radius, positive("m").needed());
    field("material", self.material, any().needed());
  }
};

// Beads listed in a CSV file: a header "x,y,radius" (m, a planar packing) or "x,y,z,radius"
// (three dimensions), optionally followed by the velocity "vx,vy" (m/s; "vx,vy,vz" in space)
// and then the angular velocity "wz" (rad/s; "wx,wy,wz" in space), then one bead per line,
// numbered in the file's order.
struct BeadListSpec {
  std::string file;  // relative to the scene file's directory
  granular::Material material;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("file", self.file, any("a CSV file with columns x,y,radius").needed());
    field("material", self.material, any().needed());
  }
};

// bottom and top along y, left and right along x, back and front along z (three dimensions)
enum class WallSide { bottom, top, left, right, back, front };
constexpr auto enum_names(WallSide) {
  using Name = std::pair<WallSide, std::string_view>;
  return std::array{Name{WallSide::bottom, "bottom"}, Name{WallSide::top, "top"},
                    Name{WallSide::left, "left"},     Name{WallSide::right, "right"},
                    Name{WallSide::back, "back"},     Name{WallSide::front, "front"}};
}

// A rigid flat wall (a line in the plane, a plane in space): on one side of the packing,
// touching its outermost beads, or through `point` with its `normal` pointing to the beads'
// side.
struct WallSpec {
  std::optional<WallSide> side;
  std::vector<double> point;   // m, [x, y] or [x, y, z]
  std::vector<double> normal;  // [nx, ny] or [nx, ny, nz], normalized when read
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
  // [row, column] in a planar lattice, [layer, row, column] in a three-dimensional one, [bead]
  // in a bead list
  std::vector<int> target;
  double radius = 0.0;           // m
  std::vector<double> velocity;  // m/s, one component per dimension
  double gap = 0.0;              // m between the striker and its target, >= 0
  // m: its path's distance from the target's centre, [o] in the plane (positive to the left of
  // its flight), [ox, oy, oz] perpendicular to its velocity in space; a number is read as [o]
  std::vector<double> offset;
  // rad/s: its angular velocity, [w] about z in the plane, [wx, wy, wz] in space; a number is
  // read as [w]
  std::vector<double> spin;
  granular::Material material;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("target", self.target,
          at_least(0, "[row, column], [layer, row, column], or [bead] in a bead list").needed());
    field("radius", self.radius, positive("m").needed());
    field("velocity", self.velocity, any("m/s, [vx, vy] or [vx, vy, vz]").needed());
    field("gap", self.gap, at_least(0.0, "m"));
    field("offset", self.offset, any("m, a number in the plane, [ox, oy, oz] in space"));
    field("spin", self.spin, any("rad/s, a number in the plane, [wx, wy, wz] in space"));
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

// A packing scene file. Bodies are the packing's beads (a lattice layer by layer and row by
// row, or the bead list's order), then the strikers.
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
  // the error asked of the answer (granular::kAccuracyRange): the run chooses its step
  std::optional<double> accuracy;
  // an LZB run against the moving geometry (docs/packings.md)
  granular::ConfigurationCheckSpec configuration_check;
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
    field("configuration_check", self.configuration_check);
    field("accuracy", self.accuracy, granular::kAccuracyRange);
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
// Throws InvalidInput naming the field when a wall's point or normal, or a striker's velocity,
// has not one component per dimension of the packing (2 in the plane, 3 in space), or a wall
// side is back or front in the plane: the check of a packing whose beads are known.
void check_dimension(const PackingScene& scene, int dimension);
// Parses and reads a scene (JSON, comments allowed).
PackingScene parse_packing_scene(std::string_view text, const std::string& source,
                                 const std::filesystem::path& directory = ".");
PackingScene load_packing_scene(const std::filesystem::path& path);

}  // namespace mimpact::packings
