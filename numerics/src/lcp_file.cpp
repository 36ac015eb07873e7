#include "mimpact/numerics/lcp_file.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include "mimpact/common/error.hpp"

namespace mimpact::numerics {

namespace {

// Reads the next number or throws, naming the file and the field expected: a finite number,
// the whole word (1e999, nan and 1.5x are refused, not read as inf, nothing or 1.5).
double next_number(std::istream& in, const std::string& source, const std::string& field) {
  std::string word;
  if (!(in >> word)) throw InvalidInput(source + ": expected " + field + ", found end of file");
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(word.c_str(), &end);
  if (end != word.c_str() + word.size() || word.empty())
    throw InvalidInput(source + ": expected " + field + ", found something not a number");
  if (!std::isfinite(value) || (errno == ERANGE && std::abs(value) > 1.0))
    throw InvalidInput(source + ": " + field + " = " + word.substr(0, 40) +
                       " is invalid; allowed: a finite number of magnitude at most 1.8e308");
  return value;
}

// Dense storage: n = 10 000 is already 800 MB for M alone.
constexpr double kLargestSize = 10000;

Eigen::Index next_size(std::istream& in, const std::string& source, const std::string& field) {
  const double value = next_number(in, source, field);
  if (!(value >= 0.0 && value == std::floor(value) && value <= kLargestSize))
    throw InvalidInput(
        source + ": " +
        invalid_value_message(field, value, "an integer in [0, 10000] (dense storage)"));
  return Eigen::Index(value);
}

}  // namespace

LcpProblem read_lcp(std::istream& in, const std::string& source) {
  const Eigen::Index n = next_size(in, source, "n (problem size)");
  const Eigen::Index storage = next_size(in, source, "storage");
  if (storage != 0)
    throw InvalidInput(source + ": " +
                       invalid_value_message("storage", double(storage),
                                             "0 (dense); sparse-block files "
                                             "are not read by this reader"));
  const Eigen::Index rows = next_size(in, source, "rows");
  const Eigen::Index columns = next_size(in, source, "columns");
  const Eigen::Index rows_again = next_size(in, source, "rows (repeated)");
  const Eigen::Index columns_again = next_size(in, source, "columns (repeated)");
  if (rows != n || columns != n || rows_again != n || columns_again != n)
    throw InvalidInput(source + ": the matrix dimensions disagree with n = " + std::to_string(n) +
                       "; allowed: an n x n matrix");
  LcpProblem problem{Eigen::MatrixXd(n, n), Eigen::VectorXd(n)};
  for (Eigen::Index column = 0; column < n; ++column)
    for (Eigen::Index row = 0; row < n; ++row)
      problem.M(row, column) =
          next_number(in, source, "M(" + std::to_string(row) + ", " + std::to_string(column) + ")");
  for (Eigen::Index i = 0; i < n; ++i)
    problem.q(i) = next_number(in, source, "q(" + std::to_string(i) + ")");
  // what follows q (Siconos files often carry a reference solution there) is not read
  return problem;
}

LcpProblem read_lcp_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InvalidInput(path.string() + ": cannot open the file for reading");
  return read_lcp(in, path.string());
}

}  // namespace mimpact::numerics
