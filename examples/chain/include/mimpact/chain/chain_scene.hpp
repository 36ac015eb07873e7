#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mimpact/chain/hertz.hpp"
#include "mimpact/numerics/contact_law.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace mimpact::chain {

// A run of beads; bead k+1 has radius (1 - taper) times bead k's.
struct SegmentSpec {
  int count = 0;
  double radius = 0.0;  // m, of the segment's first bead
  double taper = 0.0;   // in [0, 1)
  Material material;
};

enum class Side { left, right };

// A bead thrown at one end of the chain.
struct StrikerSpec {
  Side side = Side::left;
  double radius = 0.0;    // m
  double velocity = 0.0;  // m/s towards the chain, > 0
  double gap = 0.0;       // m between the striker and the end bead, >= 0
  Material material;
};

// A rigid immovable wall touching the last bead on the right.
struct WallSpec {
  Material material;
};

// What `mimpact chain --out` writes as time series: the force of these contacts and the
// velocity of these bodies, every `every` impulse steps.
struct RecordSpec {
  std::vector<int> contacts;
  std::vector<int> bodies;
  int every = 1;          // LZB: one sample every this many impulse steps
  double interval = 1e-7; // compliant: one sample every this long (s)
};

// How the impact is computed: the LZB impulse dynamics (the default) or the compliant contacts
// integrated in time (its reference for e = 1; the only one for a precompressed chain).
enum class Method { lzb, compliant };

struct CompliantSpec {
  double tolerance = 1e-10;  // relative error control of the integration
  std::optional<double> end_time;  // s; required with a precompression
};

struct ContactSpec {
  numerics::ComplianceModel model = numerics::ComplianceModel::bi_stiffness;
  double exponent = 1.5;
  double restitution = 1.0;
  // K (N/m^eta) of every contact; when absent, Hertz's, which needs exponent 3/2
  std::optional<double> stiffness;
};

// A chain scene file (the format: docs/scenes.md). Bodies are numbered left to right: a
// left striker, the beads, a right striker; contact i joins bodies i and i + 1, and the
// wall's contact, if any, comes last.
struct ChainScene {
  std::vector<SegmentSpec> segments;
  std::vector<StrikerSpec> strikers;  // one or two, on different sides
  std::optional<WallSpec> wall;
  ContactSpec contact;
  std::optional<double> delta_p;  // N s, from "impact": {"delta_p"}
  // from "impact": {"fixed_thresholds": {"velocity", "energy"}}; absent: scaled with delta_p
  std::optional<numerics::LzbOptions::FixedThresholds> fixed_thresholds;
  RecordSpec record;
  Method method = Method::lzb;
  CompliantSpec compliant;
  // N: a constant force on the first bead pushes the chain against its wall (compliant only)
  double precompression = 0.0;

  int bead_count() const;
  int body_count() const { return bead_count() + int(strikers.size()); }
  int contact_count() const { return body_count() - 1 + (wall ? 1 : 0); }
  const StrikerSpec* striker(Side side) const;
  // The LZB integrator's options for this scene at delta_p = impulse_step (N s)
  numerics::LzbOptions lzb_options(double impulse_step) const;
};

// Parses and validates a scene (JSON, comments allowed). Throws InvalidInput naming the
// source, the field, its value and what is allowed; unknown keys are errors.
ChainScene parse_chain_scene(std::string_view text, const std::string& source);
ChainScene load_chain_scene(const std::filesystem::path& path);

}  // namespace mimpact::chain
