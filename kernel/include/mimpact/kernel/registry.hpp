#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "mimpact/kernel/one_step_integrator.hpp"
#include "mimpact/kernel/one_step_ns_problem.hpp"
#include "mimpact/kernel/parameters.hpp"
#include "mimpact/numerics/error.hpp"

namespace mimpact::kernel {

// Factories by name, so that a scene can ask for "lzb" or "event-driven" while the kernel
// names no concrete law or integrator. Plugins add theirs (plugins::register_plugins()).
template <class Product>
class Registry {
 public:
  using Factory = std::function<std::unique_ptr<Product>(const Parameters&)>;

  void add(const std::string& name, Factory factory) { factories_[name] = std::move(factory); }

  // Throws InvalidInput naming the unknown name and the registered ones.
  std::unique_ptr<Product> create(const std::string& name,
                                  const Parameters& parameters = {}) const {
    const auto found = factories_.find(name);
    if (found == factories_.end()) {
      std::string known;
      for (const auto& [key, factory] : factories_) known += (known.empty() ? "" : ", ") + key;
      throw InvalidInput("no " + kind_ + " named \"" + name + "\"; registered: " +
                         (known.empty() ? "none (call plugins::register_plugins())" : known));
    }
    return found->second(parameters);
  }

  std::vector<std::string> names() const {
    std::vector<std::string> result;
    for (const auto& [key, factory] : factories_) result.push_back(key);
    return result;
  }

  explicit Registry(std::string kind) : kind_(std::move(kind)) {}

 private:
  std::string kind_;
  std::map<std::string, Factory> factories_;
};

// The process-wide registries.
Registry<OneStepIntegrator>& integrators();
Registry<ImpactProblem>& impact_problems();
Registry<ContactForceProblem>& contact_force_problems();

}  // namespace mimpact::kernel
