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

std::unique_ptr<granular::ProgressMeter> progress_line(bool quiet) {
  if (quiet || !isatty(STDERR_FILENO)) return nullptr;
  return std::make_unique<granular::ProgressMeter>(granular::stream_sink(stderr));
}

}  // namespace mimpact::cli
