#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "mimpact/common/error.hpp"
#include "mimpact/kernel/one_step_integrator.hpp"
#include "mimpact/kernel/one_step_ns_problem.hpp"
#include "mimpact/kernel/parameters.hpp"

namespace mimpact::kernel {

// Factories by name, so that a scene can ask for "lzb" or "event-driven" while the kernel
// names no concrete law or integrator. Plugins add theirs (plugins::register_plugins()).
template <class Product>
class Registry {
 public:
  using Factory = std::function<std::unique_ptr<Product>(const Parameters&)>;

  explicit Registry(std::string kind) : kind_(std::move(kind)) {}

  // A factory of its own; `defaults` are the parameters it takes, with their default values.
  void add(const std::string& name, Factory factory, Parameters defaults = Parameters::object()) {
    entries_[name] = {std::move(factory), std::move(defaults)};
  }

  // A plugin made from its options struct, Plugin::Options, whose fields the parameters name
  // (parameters.hpp): misspelt names, wrong types and values out of range are errors.
  template <class Plugin>
  void add(const std::string& name) {
    add(
        name,
        [owner = kind_ + " \"" + name + "\""](const Parameters& parameters) {
          return std::unique_ptr<Product>(std::make_unique<Plugin>(
              options_from<typename Plugin::Options>(parameters, {.name = owner})));
        },
        to_parameters(typename Plugin::Options{}));
  }

  // Throws InvalidInput naming the unknown name and the registered ones.
  std::unique_ptr<Product> create(const std::string& name,
                                  const Parameters& parameters = Parameters::object()) const {
    return entry(name).factory(parameters);
  }

  // Every parameter `name` takes, with its default value.
  const Parameters& defaults(const std::string& name) const { return entry(name).defaults; }

  std::vector<std::string> names() const {
    std::vector<std::string> result;
    for (const auto& [key, entry] : entries_) result.push_back(key);
    return result;
  }

 private:
  struct Entry {
    Factory factory;
    Parameters defaults;
  };

  // Throws InvalidInput naming the unknown name and the registered ones.
  const Entry& entry(const std::string& name) const {
    const auto found = entries_.find(name);
    if (found == entries_.end()) {
      const std::vector<std::string> known = names();
      std::string list;
      for (const std::string& key : known) list += (list.empty() ? "" : ", ") + key;
      throw InvalidInput("no " + kind_ + " named \"" + name + "\"; registered: " +
                         (list.empty() ? "none (call plugins::register_plugins())" : list));
    }
    return found->second;
  }

  std::string kind_;
  std::map<std::string, Entry> entries_;
};

// The process-wide registries.
Registry<OneStepIntegrator>& integrators();
Registry<ImpactProblem>& impact_problems();
Registry<ContactForceProblem>& contact_force_problems();

}  // namespace mimpact::kernel
