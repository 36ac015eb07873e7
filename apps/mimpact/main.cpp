// mimpact: the command line of the library; kUsage lists its commands.
#include <boost/program_options/errors.hpp>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "mimpact/common/error.hpp"

namespace {

constexpr const char* kUsage =
    "usage: mimpact COMMAND [ARGS]\n"
    "commands:\n"
    "  chain SCENE.json [--out DIR] [--delta-p X] [--tolerance eps+ [eps]] [--quiet]\n"
    "      the multiple impact of a granular chain; prints summary.json or writes it to DIR\n"
    "  packing SCENE.json [--out DIR] [--delta-p X] [--quiet]\n"
    "      the multiple impact of a packing of beads, in the plane or in space; prints\n"
    "      summary.json or writes it with the geometry, time series and frames to DIR\n"
    "  lcp FILE [--max-pivots N]\n"
    "      solves the LCP of FILE (Siconos test format) with Lemke's method; prints JSON\n"
    "  converge SCENE.json [--from h] [--tolerance eps+ [eps]] [--halvings N] [--json]\n"
    "      delta_p = h, h/2, ... until the impact converges (Nguyen & Brogliato 2011, appendix "
    "A.2)\n"
    "  nesterenko F1,F2,... [--radius a] [--static-force F0] [--site beads|sensor] ...\n"
    "      speed and width of Nesterenko's solitary waves (Coste, Falcon & Fauve 1997) for these "
    "peak forces\n"
    "run 'mimpact COMMAND --help' for the options of a command\n";

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << kUsage;
    return 2;
  }
  const std::string command = argv[1];
  const std::vector<std::string> arguments(argv + 2, argv + argc);
  try {
    if (command == "chain") return mimpact::cli::chain_command(arguments);
    if (command == "packing") return mimpact::cli::packing_command(arguments);
    if (command == "lcp") return mimpact::cli::lcp_command(arguments);
    if (command == "nesterenko") return mimpact::cli::nesterenko_command(arguments);
    if (command == "converge") return mimpact::cli::converge_command(arguments);
    if (command == "--help" || command == "-h" || command == "help") {
      std::cout << kUsage;
      return 0;
    }
    std::cerr << "mimpact: unknown command \"" << command
              << "\"; allowed: chain, converge, lcp, nesterenko, packing\n"
              << kUsage;
    return 2;
  } catch (const boost::program_options::error& error) {
    std::cerr << "mimpact " << command << ": " << error.what() << "\n";
    return 2;
  } catch (const mimpact::Error& error) {
    std::cerr << "mimpact " << command << ": error: " << error.what() << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "mimpact " << command
              << ": error: out of memory; the problem is too large for this machine\n";
    return 1;
  } catch (const std::exception& error) {
    // a library below mimpact (Boost, nlohmann::json, the standard library) refused: still one
    // line and a failure status, never an abort
    std::cerr << "mimpact " << command << ": error: " << error.what() << "\n";
    return 1;
  }
}
