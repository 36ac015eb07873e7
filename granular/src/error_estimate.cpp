#include "mimpact/granular/error_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "mimpact/numerics/lzb_adaptive_options.hpp"

namespace mimpact::granular {

namespace {

// The measured ratios of a companion's difference to the true error, at r = 2 for delta_p and
// r = 10 for a tolerance (docs/design/error_estimates.md): 0.93 to 1.00 of (r - 1) for delta_p,
// 0.11 to 7 of (r - 1) for a tolerance; these factors make the estimate bound the true error.
constexpr double kDeltaPSafety = 2.0;
constexpr double kToleranceSafety = 3.0;

// `step` times `ratio` where that stays at most `largest`, else divided by it; the ratio taken.
double companion_ratio(double step, double ratio, double largest) {
  return step * ratio <= largest ? ratio : 1.0 / ratio;
}

std::string said(const std::string& what, double ratio, double scale) {
  char text[160];
  std::snprintf(text, sizeof text, "a companion run at %.3g x the %s, its difference x %.3g", ratio,
                what.c_str(), scale);
  return text;
}

}  // namespace

Companion companion_of(const ContactModel& model, Method method,
                       const plugins::LzbImpactOptions& impact, const CompliantSpec& compliant) {
  Companion companion{.impact = impact, .compliant = compliant};
  double ratio = 1.0, safety = 1.0;
  std::string what;
  if (method == Method::compliant) {
    const bool frozen = compliant.geometry == Geometry::frozen || !model.beads;
    ratio = companion_ratio(
        compliant.tolerance, 10.0,
        frozen ? CompliantSpec::kLoosestFrozenTolerance : CompliantSpec::kLoosestTolerance);
    companion.compliant.tolerance = compliant.tolerance * ratio;
    safety = kToleranceSafety;
    what = "tolerance";
  } else if (impact.chosen_integrator() == plugins::LzbIntegrator::adaptive) {
    ratio = companion_ratio(impact.adaptive_tolerance(), 10.0,
                            numerics::LzbAdaptiveOptions::kToleranceRange.upper);
    companion.impact.tolerance = impact.adaptive_tolerance() * ratio;
    safety = kToleranceSafety;
    what = "tolerance";
  } else {
    if (impact.delta_p) {
      ratio = companion_ratio(*impact.delta_p, 2.0, 0.5 * smallest_momentum(model));
      companion.impact.delta_p = *impact.delta_p * ratio;
    } else {
      ratio = companion_ratio(*impact.relative_delta_p, 2.0, 0.5);
      companion.impact.relative_delta_p = *impact.relative_delta_p * ratio;
    }
    if (ratio < 1.0) companion.impact.impulse_steps.max_steps *= 2;
    safety = kDeltaPSafety;
    what = "delta_p";
  }
  companion.scale = safety / std::abs(ratio - 1.0);
  companion.method = said(what, ratio, companion.scale);
  return companion;
}

ErrorEstimate estimate_error(const ContactModel& model, const Eigen::VectorXd& velocity,
                             const Eigen::VectorXd& companion_velocity,
                             const Companion& companion) {
  const int d = model.dimension;
  const Eigen::Index bodies = model.body_count();
  double fastest = 0.0, sum = 0.0, worst = 0.0;
  for (Eigen::Index b = 0; b < bodies; ++b) {
    fastest = std::max(fastest, model.velocity.segment(d * b, d).norm());
    const double error = companion.scale *
                         (velocity.segment(d * b, d) - companion_velocity.segment(d * b, d)).norm();
    sum += error * error;
    worst = std::max(worst, error);
  }
  return {.rms = std::sqrt(sum / double(bodies)) / fastest,
          .worst = worst / fastest,
          .method = companion.method};
}

nlohmann::ordered_json error_estimate_json(const std::optional<ErrorEstimate>& estimate) {
  if (!estimate) return nullptr;
  return {{"rms", estimate->rms},
          {"worst", estimate->worst},
          {"method", estimate->method},
          {"companion_seconds", estimate->companion_seconds}};
}

}  // namespace mimpact::granular
