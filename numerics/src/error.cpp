#include "mimpact/numerics/error.hpp"

#include <charconv>

namespace mimpact {

std::string invalid_value_message(const std::string& field, double value,
                                  const std::string& allowed) {
  char number[32];
  // the shortest text that reads back as the same double: -1e-05, not -1.0000000000000001e-05
  const auto end = std::to_chars(number, number + sizeof number, value).ptr;
  return field + " = " + std::string(number, end) + " is invalid; allowed: " + allowed;
}

}  // namespace mimpact
