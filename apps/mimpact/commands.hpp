#pragma once

#include <string>
#include <vector>

namespace mimpact::cli {

// Each command takes its own arguments (after the command name) and returns the exit code.
// Bad input throws mimpact::Error or boost::program_options::error; main reports them.
int chain_command(const std::vector<std::string>& arguments);
int lcp_command(const std::vector<std::string>& arguments);
int nesterenko_command(const std::vector<std::string>& arguments);
int packing_command(const std::vector<std::string>& arguments);
int converge_command(const std::vector<std::string>& arguments);

}  // namespace mimpact::cli
