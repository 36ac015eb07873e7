#pragma once

#include <boost/program_options.hpp>
#include <string>
#include <vector>

namespace mimpact::cli {

// Parses a command's arguments: the options of `visible` (which gets "--help") and one
// required positional argument stored in `positional`. Returns false after printing the
// help when --help is given; throws boost::program_options::error on bad arguments.
bool parse_command_line(const std::vector<std::string>& arguments,
                        boost::program_options::options_description& visible,
                        const std::string& positional_name, std::string& positional,
                        boost::program_options::variables_map& values);

}  // namespace mimpact::cli
