#include <boost/program_options.hpp>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "command_line.hpp"
#include "commands.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/numerics/lcp_file.hpp"
#include "mimpact/numerics/lemke.hpp"

namespace mimpact::cli {

namespace po = boost::program_options;

namespace {

// The file name is the user's bytes, not always UTF-8: replace what JSON cannot hold.
std::string dump(const nlohmann::ordered_json& value) {
  return value.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace

int lcp_command(const std::vector<std::string>& arguments) {
  std::string file;
  numerics::LemkeOptions options;
  po::options_description visible("mimpact lcp FILE: Lemke's method on an LCP file");
  visible.add_options()("max-pivots", po::value(&options.max_pivots)->default_value(0),
                        "pivot limit (0: 1000 + 100 n)");
  po::variables_map values;
  if (!parse_command_line(arguments, visible, "file", file, values)) return 0;
  validate(options, "--max-pivots");

  numerics::LcpProblem problem;
  try {
    problem = numerics::read_lcp_file(file);
  } catch (const InvalidInput& error) {
    // still one JSON object on stdout, so scripts see the outcome of every file
    std::cout << dump(nlohmann::ordered_json{
                     {"file", file}, {"status", "invalid"}, {"message", error.what()}})
              << "\n";
    throw;
  }
  numerics::LemkeResult result = numerics::solve_lemke(problem.M, problem.q, options);
  nlohmann::ordered_json out = {{"file", file},
                                {"status", numerics::to_string(result.status)},
                                {"n", problem.q.size()},
                                {"pivots", result.pivots}};
  // a point beyond double precision (never a solved one) is not printed: JSON has no NaN
  if (std::isfinite(result.complementarity_error))
    out["complementarity_error"] = result.complementarity_error;
  if (result.z.allFinite() && result.w.allFinite()) {
    out["z"] = std::vector<double>(result.z.data(), result.z.data() + result.z.size());
    out["w"] = std::vector<double>(result.w.data(), result.w.data() + result.w.size());
  } else {
    result.message += (result.message.empty() ? "" : "; ") +
                      std::string(
                          "the last point has entries beyond double precision (z, w not "
                          "printed)");
  }
  if (!result.message.empty()) out["message"] = result.message;
  std::cout << dump(out) << "\n";
  // a ray or a pivot limit is an outcome, reported in "status"; only bad input fails
  return result.status == numerics::LemkeStatus::invalid_input ? 1 : 0;
}

}  // namespace mimpact::cli
