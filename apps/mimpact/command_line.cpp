#include "command_line.hpp"

#include <unistd.h>

#include <cstdio>
#include <iostream>

namespace mimpact::cli {

namespace po = boost::program_options;

bool parse_command_line(const std::vector<std::string>& arguments, po::options_description& visible,
                        const std::string& positional_name, std::string& positional,
                        po::variables_map& values) {
  visible.add_options()("help,h", "this help");
  po::options_description all;
  all.add(visible).add_options()(positional_name.c_str(), po::value(&positional)->required());
  po::positional_options_description position;
  position.add(positional_name.c_str(), 1);
  po::store(po::command_line_parser(arguments).options(all).positional(position).run(), values);
  if (values.count("help")) {
    std::cout << visible << "\n";
    return false;
  }
  if (!values.count(positional_name))
    throw po::error("missing the " + positional_name + " argument (--help for usage)");
  po::notify(values);
  return true;
}

std::unique_ptr<granular::ProgressMeter> progress_line(bool quiet,
                                                       const granular::RunLimits& limits) {
  const bool shown = !quiet && isatty(STDERR_FILENO);
  return granular::run_meter(shown ? granular::stream_sink(stderr) : nullptr, limits.seconds,
                             limits.seconds_option);
}

void add_run_limit_options(po::options_description& visible, granular::RunLimits& limits) {
  visible.add_options()(
      "max-seconds", po::value(&limits.seconds),
      "wall-clock seconds the run may take (its impact, checks and estimates; no limit by "
      "default): past them it stops with an error and writes nothing, as LAMMPS's `timer "
      "timeout` does")(
      "threads", po::value(&limits.threads),
      "2 (the default): the error estimate's companion runs beside the run, on a second core; "
      "1: after it");
}

void add_accuracy_options(boost::program_options::options_description& visible) {
  visible.add_options()(
      "accuracy", boost::program_options::value<double>(),
      "the error asked of the post-impact velocities, a share of the fastest speed before the "
      "impact (1e-12 to 0.1): the run chooses its tolerance (or delta_p) and runs again until its "
      "estimate meets it; overrides the scene's accuracy, delta_p and tolerance")(
      "no-error-estimate",
      "skip the companion run that estimates the answer's error (it costs 0.3 to 0.6 x the run "
      "for delta_p, 1.0 to 1.6 x for a tolerance; a run asked for an accuracy makes it all the "
      "same)");
}

void read_accuracy_options(const boost::program_options::variables_map& values,
                           granular::ImpactOverrides& overrides,
                           granular::SceneRunOptions& run_options) {
  overrides.accuracy_name = "--accuracy";
  if (values.count("accuracy")) overrides.accuracy = values["accuracy"].as<double>();
  run_options.estimate_error = values.count("no-error-estimate") == 0;
}

}  // namespace mimpact::cli
