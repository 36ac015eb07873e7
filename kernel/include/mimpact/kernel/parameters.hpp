#pragma once

#include <initializer_list>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>

namespace mimpact::kernel {

// Named numeric settings handed to a plugin's factory, e.g. {"delta_p", 1e-6}. A factory
// reads what it knows and rejects the rest, so a misspelt name is an error, not ignored.
class Parameters {
 public:
  Parameters() = default;
  Parameters(std::initializer_list<std::pair<const std::string, double>> values)
      : values_(values) {}

  void set(const std::string& name, double value) { values_[name] = value; }
  bool has(const std::string& name) const { return values_.count(name) > 0; }
  double get(const std::string& name, double fallback) const;
  // An integer parameter: throws InvalidInput naming it unless its value is a whole number
  // in [lowest, highest] (a 2.7 or a 1e300 is an error, not a truncation).
  std::int64_t get_integer(const std::string& name, std::int64_t fallback, std::int64_t lowest,
                           std::int64_t highest) const;
  // Throws InvalidInput naming the first parameter not in `known`, for plugin `owner`.
  void allow_only(std::string_view owner, std::initializer_list<std::string_view> known) const;

 private:
  std::map<std::string, double> values_;
};

}  // namespace mimpact::kernel
