#pragma once

#include <filesystem>
#include <istream>
#include <string>

#include "mimpact/numerics/lcp_problem.hpp"

namespace mimpact::numerics {

// Reads an LCP in the text format of the Siconos numerics test suite:
//   n, storage (0 = dense), rows, columns, rows and columns again, the n*n entries of M,
//   then the n entries of q; anything after is ignored (known solutions, comments).
// The entries of M fill it COLUMN by column: each printed line is a column of M.
// Sparse-block files (storage 1) are refused with an InvalidInput that says so, as is any
// malformed or truncated file; `source` names the input in the message.
LcpProblem read_lcp(std::istream& in, const std::string& source);
LcpProblem read_lcp_file(const std::filesystem::path& path);

}  // namespace mimpact::numerics
