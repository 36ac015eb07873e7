#pragma once

#include <boost/program_options.hpp>
#include <memory>
#include <string>
#include <vector>

#include "mimpact/granular/progress_meter.hpp"
#include "mimpact/granular/run_limits.hpp"
#include "mimpact/granular/scene_run.hpp"

namespace mimpact::cli {

// Parses a command's arguments: the options of `visible` (which gets "--help") and one
// required positional argument stored in `positional`. Returns false after printing the
// help when --help is given; throws boost::program_options::error on bad arguments.
bool parse_command_line(const std::vector<std::string>& arguments,
                        boost::program_options::options_description& visible,
                        const std::string& positional_name, std::string& positional,
                        boost::program_options::variables_map& values);

// The meter of a run: its progress line on stderr, in place (none with --quiet or when stderr
// is not a terminal), and its --max-seconds; null when it has neither.
std::unique_ptr<granular::ProgressMeter> progress_line(bool quiet,
                                                       const granular::RunLimits& limits);

// --max-seconds and --threads, into limits.seconds and limits.threads, of the chain and packing
// commands.
void add_run_limit_options(boost::program_options::options_description& visible,
                           granular::RunLimits& limits);

// --accuracy and --no-error-estimate, of the chain and packing commands.
void add_accuracy_options(boost::program_options::options_description& visible);
// Their values: the accuracy over the scene's (and its step rule), and the error estimate, on
// unless --no-error-estimate.
void read_accuracy_options(const boost::program_options::variables_map& values,
                           granular::ImpactOverrides& overrides,
                           granular::SceneRunOptions& run_options);

}  // namespace mimpact::cli
