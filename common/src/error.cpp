#include "mimpact/common/error.hpp"

#include <charconv>
#include <cstdio>

namespace mimpact {

std::string to_text(double value) {
  char number[32];
  const auto end = std::to_chars(number, number + sizeof number, value).ptr;
  return std::string(number, end);
}

std::string rounded_text(double value) {
  char number[32];
  std::snprintf(number, sizeof number, "%.3g", value);
  return number;
}

std::string invalid_value_message(const std::string& field, double value,
                                  const std::string& allowed) {
  return field + " = " + to_text(value) + " is invalid; allowed: " + allowed;
}

}  // namespace mimpact
