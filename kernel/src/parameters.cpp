#include "mimpact/kernel/parameters.hpp"

#include <cmath>
#include <string>

#include "mimpact/numerics/error.hpp"

namespace mimpact::kernel {

double Parameters::get(const std::string& name, double fallback) const {
  const auto found = values_.find(name);
  return found == values_.end() ? fallback : found->second;
}

std::int64_t Parameters::get_integer(const std::string& name, std::int64_t fallback,
                                     std::int64_t lowest, std::int64_t highest) const {
  const auto found = values_.find(name);
  if (found == values_.end()) return fallback;
  const double value = found->second;
  if (!(value == std::floor(value) && value >= double(lowest) && value <= double(highest)))
    throw InvalidInput(invalid_value_message(name, value, "an integer in [" + std::to_string(lowest) + ", " +
                                                              std::to_string(highest) + "]"));
  return std::int64_t(value);
}

void Parameters::allow_only(std::string_view owner,
                            std::initializer_list<std::string_view> known) const {
  for (const auto& [name, value] : values_) {
    bool listed = false;
    for (std::string_view k : known) listed = listed || name == k;
    if (!listed) {
      std::string allowed;
      for (std::string_view k : known) allowed += (allowed.empty() ? "" : ", ") + std::string(k);
      throw InvalidInput(std::string(owner) + ": unknown parameter \"" + name +
                         "\"; allowed: " + (allowed.empty() ? "none" : allowed));
    }
  }
}

}  // namespace mimpact::kernel
