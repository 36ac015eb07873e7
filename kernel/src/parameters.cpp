#include "mimpact/kernel/parameters.hpp"

#include "mimpact/numerics/error.hpp"

namespace mimpact::kernel {

double Parameters::get(const std::string& name, double fallback) const {
  const auto found = values_.find(name);
  return found == values_.end() ? fallback : found->second;
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
