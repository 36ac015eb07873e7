#include <boost/program_options.hpp>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "command_line.hpp"
#include "commands.hpp"
#include "mimpact/analysis/nesterenko.hpp"
#include "mimpact/common/error.hpp"

namespace mimpact::cli {

namespace po = boost::program_options;

namespace {

std::vector<double> parse_forces(const std::string& text) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || !(value > 0.0 && std::isfinite(value)))
      throw InvalidInput("FORCES: \"" + item +
                         "\" is invalid; allowed: finite forces > 0 (N), comma-separated");
    values.push_back(value);
  }
  if (values.empty())
    throw InvalidInput("FORCES is empty; allowed: finite forces > 0 (N), comma-separated");
  return values;
}

}  // namespace

int nesterenko_command(const std::vector<std::string>& arguments) {
  analysis::BeadChain chain{0.004, 2.26e11, 0.3, 7650.0};
  double static_force = 0.0;
  std::string site = "beads", forces_text;
  int shape = 0;
  po::options_description visible(
      "mimpact nesterenko FORCES: solitary-wave theory of Coste, Falcon & Fauve (1997) for peak "
      "forces F1,F2,... (N)");
  visible.add_options()("radius", po::value(&chain.radius)->default_value(chain.radius),
                        "bead radius a (m)")(
      "young", po::value(&chain.young)->default_value(chain.young), "Young's modulus (Pa)")(
      "poisson", po::value(&chain.poisson)->default_value(chain.poisson), "Poisson's ratio")(
      "density", po::value(&chain.density)->default_value(chain.density), "density (kg/m^3)")(
      "static-force", po::value(&static_force)->default_value(0.0), "static force F_0 (N)")(
      "site", po::value(&site)->default_value(site),
      "where F is felt: beads (sphere-sphere) or sensor (plane-sphere)")(
      "shape", po::value(&shape)->default_value(0),
      "also print the pulse F(t) of the first force at this many times");
  po::variables_map values;
  if (!parse_command_line(arguments, visible, "forces", forces_text, values)) return 0;
  if (site != "beads" && site != "sensor")
    throw InvalidInput("--site \"" + site + "\" is invalid; allowed: beads, sensor");
  if (!(static_force >= 0.0 && std::isfinite(static_force)))
    throw InvalidInput(
        invalid_value_message("--static-force", static_force, "a finite F_0 >= 0 (N)"));
  if (shape != 0 && !(shape >= 2 && shape <= 1'000'000))
    throw InvalidInput(invalid_value_message("--shape", shape, "0 (no pulse) or 2 to 1e6 samples"));
  const analysis::ForceSite where =
      site == "sensor" ? analysis::ForceSite::sensor : analysis::ForceSite::between_beads;
  const std::vector<double> forces = parse_forces(forces_text);

  nlohmann::ordered_json out{{"theta", chain.theta()},
                             {"C", chain.C()},
                             {"mass", chain.mass()},
                             {"static_force", static_force},
                             {"site", site}};
  nlohmann::ordered_json waves = nlohmann::ordered_json::array();
  for (double force : forces) {
    if (static_force == 0.0) {
      const double speed = analysis::solitary_wave_speed(chain, force, where);
      waves.push_back({{"peak_force", force},
                       {"speed", speed},
                       {"width", analysis::solitary_wave_width(chain, speed)}});
    } else {
      const analysis::PrecompressedWave wave =
          analysis::precompressed_solitary_wave(chain, force, static_force, where);
      waves.push_back({{"peak_force", force},
                       {"speed", wave.speed},
                       {"sound_speed", wave.sound_speed},
                       {"strain_ratio", wave.strain_ratio},
                       {"y_infinity", wave.y_infinity}});
    }
  }
  out["waves"] = waves;
  if (shape > 1) {
    nlohmann::ordered_json samples = nlohmann::ordered_json::array();
    if (static_force > 0.0) {
      for (const auto& [t, f] :
           analysis::precompressed_pulse(chain, forces.front(), static_force, where, shape))
        samples.push_back({t, f});
    } else {
      const double speed = analysis::solitary_wave_speed(chain, forces.front(), where);
      const double width = analysis::solitary_wave_width(chain, speed);
      for (int k = 0; k < shape; ++k) {
        const double t = 0.5 * M_PI * width * k / (shape - 1);
        samples.push_back({t, forces.front() * std::pow(std::cos(t / width), 6)});
      }
    }
    out["shape"] = samples;
  }
  std::cout << out.dump(2) << "\n";
  return 0;
}

}  // namespace mimpact::cli
