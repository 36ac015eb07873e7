#include "mimpact/plugins/lzb_impact_options.hpp"

#include <utility>

#include "mimpact/common/error.hpp"

namespace mimpact::plugins {

numerics::LzbOptions LzbImpactOptions::impulse_step_options() const {
  numerics::LzbOptions options = impulse_steps;
  options.delta_p = delta_p.value_or(kDefaultDeltaP);
  options.relative_delta_p = relative_delta_p;
  return options;
}

numerics::LzbAdaptiveOptions LzbImpactOptions::adaptive_options() const {
  numerics::LzbAdaptiveOptions options = adaptive;
  options.tolerance = adaptive_tolerance();
  options.max_steps = impulse_steps.max_steps;
  options.sampled_contacts = impulse_steps.sampled_contacts;
  return options;
}

std::string LzbImpactOptions::conflict(const fields::Labels& labels) const {
  const std::string integrator_is =
      labels("integrator") + " is \"" + std::string(enum_name(chosen_integrator())) + "\"";
  if (integrator == LzbIntegrator::adaptive) {
    for (const auto& [name, value] :
         {std::pair{"delta_p", delta_p}, std::pair{"relative_delta_p", relative_delta_p}})
      if (value)
        return labels(name) + " = " + to_text(*value) +
               " chooses the step of the impulse steps, but " + integrator_is +
               "; allowed: " + labels("tolerance") +
               " with \"adaptive\", or a step with \"impulse-step\" or \"asynchronous\"";
  } else if (tolerance) {
    return labels("tolerance") + " = " + to_text(*tolerance) +
           " is the accuracy of the adaptive integrator, but " + integrator_is +
           "; allowed: " + labels("delta_p") + " or " + labels("relative_delta_p") +
           " with the impulse steps, or a tolerance with \"adaptive\"";
  }
  if (delta_p && relative_delta_p)
    return labels("delta_p") + " = " + to_text(*delta_p) + " and " + labels("relative_delta_p") +
           " = " + to_text(*relative_delta_p) +
           " both choose the impulse step; allowed: one of them";
  return {};
}

void LzbImpactOptions::check(std::string_view owner, const fields::Labels& labels) const {
  // the fields' ranges, each named where it was given
  const fields::Validator validator{std::string(owner), ""};
  visit_fields(*this, [&](std::string_view name, const auto& value, const auto&... allowed) {
    validator.check(labels(name), value, allowed...);
  });
  if (const std::string message = conflict(labels); !message.empty())
    throw InvalidInput(owner.empty() ? message : std::string(owner) + ": " + message);
}

std::unique_ptr<numerics::ImpactIntegrator> make_impact_integrator(
    const LzbImpactOptions& options) {
  for (const ImpactIntegratorRegistration& registration : kImpactIntegrators)
    if (registration.id == options.chosen_integrator()) return registration.make(options);
  throw Error("the LZB integrator " +
              std::to_string(static_cast<int>(options.chosen_integrator())) +
              " is not registered in kImpactIntegrators");
}

}  // namespace mimpact::plugins
