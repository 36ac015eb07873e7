#pragma once

#include <Eigen/Dense>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "mimpact/common/fields.hpp"
#include "mimpact/numerics/impact_integrator.hpp"
#include "mimpact/numerics/lzb_adaptive_integrator.hpp"
#include "mimpact/numerics/lzb_asynchronous_integrator.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace mimpact::plugins {

// How the LZB impact is integrated: by the impulse steps of Nguyen & Brogliato (2011), first
// order in delta_p; by the same steps taken by each contact at its own pace
// (numerics::LzbAsynchronousIntegrator, for impacts whose loaded contacts far outnumber the
// front's: packings); or by the adaptive integration of their continuous limit to a tolerance
// (numerics::LzbAdaptiveIntegrator).
// Each is registered once, in kImpactIntegrators below.
enum class LzbIntegrator { impulse_step, asynchronous, adaptive };

// The options of the "lzb" impact problem: one value, whether it comes from a scene's "impact",
// the parameters of a registry, the command line or Python's keyword arguments, checked by one
// rule (check()). The choices whose presence matters are optional: a step given to the adaptive
// integrator, or two steps at once, are refused rather than silently ignored.
struct LzbImpactOptions {
  // delta_p when neither it nor relative_delta_p is given (N s)
  static constexpr double kDefaultDeltaP = 1e-5;

  // The impulse steps when none is chosen (chosen_integrator()).
  std::optional<LzbIntegrator> integrator;
  // The impulse steps' principal step (N s), synchronous or asynchronous.
  std::optional<double> delta_p;
  // Or this share of each impact's natural impulse (numerics::LzbOptions::relative_delta_p).
  std::optional<double> relative_delta_p;
  // The adaptive integrator's relative accuracy (LzbAdaptiveOptions::tolerance).
  std::optional<double> tolerance;
  // The impulse steps' other options; max_steps and sampled_contacts (interactions of the
  // system) serve the adaptive integrator too. Their delta_p and relative_delta_p are the ones
  // above.
  numerics::LzbOptions impulse_steps;
  // The adaptive integrator's sample_interval, within_steps_from and events_per_contact (its
  // other options come
  // from the fields above).
  numerics::LzbAdaptiveOptions adaptive;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("integrator", self.integrator);
    field("delta_p", self.delta_p, positive("N s"));
    field("relative_delta_p", self.relative_delta_p, numerics::LzbOptions::kRelativeDeltaPRange);
    field("tolerance", self.tolerance, numerics::LzbAdaptiveOptions::kToleranceRange);
    numerics::LzbOptions::visit_fields(self.impulse_steps,
                                       [&](std::string_view name, auto& value, auto&&... allowed) {
                                         if (name != "delta_p" && name != "relative_delta_p")
                                           field(name, value, allowed...);
                                       });
    numerics::LzbAdaptiveOptions::visit_fields(self.adaptive, [&](std::string_view name,
                                                                  auto& value, auto&&... allowed) {
      if (name == "sample_interval" || name == "within_steps_from" || name == "events_per_contact")
        field(name, value, allowed...);
    });
  }

  LzbIntegrator chosen_integrator() const {
    return integrator.value_or(LzbIntegrator::impulse_step);
  }
  // The impulse steps' options, delta_p and relative_delta_p included.
  numerics::LzbOptions impulse_step_options() const;
  // The adaptive integrator's options, with max_steps and sampled_contacts from impulse_steps.
  numerics::LzbAdaptiveOptions adaptive_options() const;
  double adaptive_tolerance() const {
    return tolerance.value_or(numerics::LzbAdaptiveOptions{}.tolerance);
  }

  // The fields' cross rules, as Ceres's TrustRegionOptionsAreValid: no field of an integrator
  // not chosen (delta_p or relative_delta_p with "adaptive", tolerance with the impulse steps),
  // nor delta_p with relative_delta_p. The message naming the fields as `labels` does
  // ("impact.delta_p" in a scene, "--delta-p" when the command line gave it), or "" when they
  // agree.
  std::string conflict(const fields::Labels& labels = {}) const;
  // The one check: every field in its range, then conflict(). Throws InvalidInput "OWNER: ...".
  void check(std::string_view owner, const fields::Labels& labels = {}) const;
};

// The registration of the impact integrators, the one place an integrator is named and made: a
// new one is its class (a numerics::ImpactIntegrator), its value in LzbIntegrator and a row here.
struct ImpactIntegratorRegistration {
  LzbIntegrator id;
  std::string_view name;  // in scenes, on the command line and in Python
  std::unique_ptr<numerics::ImpactIntegrator> (*make)(const LzbImpactOptions& options);
};

inline constexpr std::array kImpactIntegrators{
    ImpactIntegratorRegistration{
        LzbIntegrator::impulse_step, "impulse-step",
        [](const LzbImpactOptions& options) -> std::unique_ptr<numerics::ImpactIntegrator> {
          return std::make_unique<numerics::LzbImpulseIntegrator>(options.impulse_step_options());
        }},
    ImpactIntegratorRegistration{
        LzbIntegrator::asynchronous, "asynchronous",
        [](const LzbImpactOptions& options) -> std::unique_ptr<numerics::ImpactIntegrator> {
          return std::make_unique<numerics::LzbAsynchronousIntegrator>(
              options.impulse_step_options());
        }},
    ImpactIntegratorRegistration{
        LzbIntegrator::adaptive, "adaptive",
        [](const LzbImpactOptions& options) -> std::unique_ptr<numerics::ImpactIntegrator> {
          return std::make_unique<numerics::LzbAdaptiveIntegrator>(options.adaptive_options());
        }},
};

// The names common/fields.hpp reads and writes LzbIntegrator by.
constexpr auto enum_names(LzbIntegrator) {
  using Name = std::pair<LzbIntegrator, std::string_view>;
  std::array<Name, kImpactIntegrators.size()> names{};
  for (std::size_t i = 0; i < names.size(); ++i)
    names[i] = {kImpactIntegrators[i].id, kImpactIntegrators[i].name};
  return names;
}

// The integrator the options choose, made with its options.
std::unique_ptr<numerics::ImpactIntegrator> make_impact_integrator(const LzbImpactOptions& options);

}  // namespace mimpact::plugins
