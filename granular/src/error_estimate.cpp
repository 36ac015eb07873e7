#include "mimpact/granular/error_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "mimpact/common/error.hpp"
#include "mimpact/numerics/lzb_adaptive_options.hpp"

namespace mimpact::granular {

namespace {

// error(k) = safety |v(k) - v(r k)| / |r - 1|, with these factors over the measured ratios of a
// companion's difference to the true error (docs/design/error_estimates.md): at r = 2 for
// delta_p, 0.93 to 1.00 of (r - 1); at r = 0.2 for a tolerance (the finer run's error a fifth to
// a half of the run's), an estimate 1.2 to 4.5 times the true error over the corpus; at r = 5,
// where a tolerance has no finer one (its finest fifth), 0.28 to 38 of (r - 1): the estimate is
// 0.83 to 113 times the true error there.
constexpr double kDeltaPSafety = 1.25;
constexpr double kFinerToleranceSafety = 1.35;
constexpr double kCoarserToleranceSafety = 3.0;
// A finer companion's budget of steps (impact.max_steps, compliant.max_steps), of the run's.
constexpr double kFinerCompanionSteps = 4.0;

// A first impulse step this many times the accuracy's share of the momentum: the impulse steps'
// error is 1 to 13 (RMS) and about 35 (worst body, C1) times delta_p / (m V), so that the first
// pair is ten to a few hundred times coarser than the answer; within these shares of the
// momentum, where the steps are first order (C1: 0.93 of the true error from the companion's
// difference at 3e-3 m V) and the pair, cheap, tells the steps the answer needs before it runs.
constexpr double kFirstDeltaP = 10.0;
// The moving geometry's first tolerance, of the accuracy: its true error is 0.01 to 0.4 of its
// tolerance on most of the corpus's packings (median 0.3; 1.4 to 12 on three), so that the first
// pair at the accuracy itself went 18 to 32 times finer than needed on the small ones.
constexpr double kFirstMovingTolerance = 10.0;
// A chain's first tolerance, of the accuracy, longer than this many bodies: accuracy x
// kChainBodies / bodies. The last bead's error grows with the chain's length (docs/model.md,
// section 10): at tolerance 1e-6, 2.6e-4 (adaptive LZB) and 6.4e-4 (compliant contacts) on
// 100 000 beads, so that with the estimate's safety the first pair at the accuracy itself missed
// it by 20 to 400 times on 1 000 to 100 000 beads and took a second pair.
constexpr double kChainBodies = 100.0;
constexpr double kFinestFirstDeltaP = 1e-3;
constexpr double kCoarsestFirstDeltaP = 1e-2;
// A refinement aims at this share of the accuracy: first order in delta_p predicts its step
// closely; a tolerance's error is proportional within a factor of about 3.
constexpr double kDeltaPAim = 0.8;
constexpr double kToleranceAim = 0.5;
// The least order a refinement takes from two runs' estimates: where the error hardly fell (the
// velocities at end_time through many collisions, docs/design/error_estimates.md, "Accuracy"),
// the next run goes as far again as the error is off squared.
constexpr double kLeastOrder = 0.5;

std::string said(const std::string& what, double ratio, double scale) {
  char text[160];
  std::snprintf(text, sizeof text, "a companion run at %.3g x the %s, its difference x %.3g", ratio,
                what.c_str(), scale);
  return text;
}

// An impulse step finer than impact.max_steps allows for `accuracy`: refused, naming the
// accuracy rather than the delta_p the run chose.
[[noreturn]] void fail_finer_than_allowed(double accuracy, double delta_p, double steps,
                                          std::int64_t max_steps) {
  throw InvalidInput("accuracy = " + to_text(accuracy) + " needs delta_p of about " +
                     to_text(delta_p) + " N s, about " + rounded_text(steps) +
                     " impulse steps, more than impact.max_steps = " + std::to_string(max_steps) +
                     "; allowed: a larger accuracy, a larger impact.max_steps, or \"integrator\": "
                     "\"adaptive\"");
}

}  // namespace

StepOptions StepRule::at(const StepOptions& options, double k) const {
  StepOptions changed = options;
  switch (kind) {
    case Kind::delta_p:
      changed.impact.delta_p = k;
      break;
    case Kind::relative_delta_p:
      changed.impact.relative_delta_p = k;
      break;
    case Kind::lzb_tolerance:
      changed.impact.tolerance = k;
      break;
    case Kind::compliant_tolerance:
      changed.compliant.tolerance = k;
      break;
  }
  return changed;
}

StepRule step_rule(const ContactModel& model, Method method, const StepOptions& options) {
  StepRule rule;
  if (method == Method::compliant) {
    const bool frozen = options.compliant.geometry == Geometry::frozen || !model.beads;
    rule = {.kind = StepRule::Kind::compliant_tolerance,
            .value = options.compliant.tolerance,
            .finest = 1e-14,
            .loosest =
                frozen ? CompliantSpec::kLoosestFrozenTolerance : CompliantSpec::kLoosestTolerance,
            .finer_safety = kFinerToleranceSafety,
            .coarser_safety = kCoarserToleranceSafety,
            .companion = 0.2,
            .name = "tolerance"};
  } else if (options.impact.chosen_integrator() == plugins::LzbIntegrator::adaptive) {
    rule = {.kind = StepRule::Kind::lzb_tolerance,
            .value = options.impact.adaptive_tolerance(),
            .finest = numerics::LzbAdaptiveOptions::kToleranceRange.lower,
            .loosest = numerics::LzbAdaptiveOptions::kToleranceRange.upper,
            .finer_safety = kFinerToleranceSafety,
            .coarser_safety = kCoarserToleranceSafety,
            .companion = 0.2,
            .name = "tolerance"};
  } else if (options.impact.delta_p) {
    rule = {.kind = StepRule::Kind::delta_p,
            .value = *options.impact.delta_p,
            .finest = largest_momentum(model) / double(options.impact.impulse_steps.max_steps),
            .loosest = 0.5 * smallest_momentum(model),
            .max_steps = options.impact.impulse_steps.max_steps,
            .finer_safety = kDeltaPSafety,
            .coarser_safety = kDeltaPSafety,
            .companion = 2.0,
            .name = "delta_p"};
  } else {
    rule = {.kind = StepRule::Kind::relative_delta_p,
            .value = options.impact.relative_delta_p.value_or(0.0),
            .finest = 0.0,
            .loosest = 0.5,
            .finer_safety = kDeltaPSafety,
            .coarser_safety = kDeltaPSafety,
            .companion = 2.0,
            .name = "delta_p"};
  }
  return rule;
}

Companion companion_at(const StepRule& rule, const StepOptions& options, double value) {
  const double ratio = value / rule.value;
  const double safety = ratio < 1.0 ? rule.finer_safety : rule.coarser_safety;
  const double scale = safety / std::abs(ratio - 1.0);
  return {.options = rule.at(options, value),
          .scale = scale,
          .method = said(rule.name, ratio, scale),
          .finer = ratio < 1.0};
}

Companion companion_of(const StepRule& rule, const StepOptions& options) {
  const double preferred = rule.value * rule.companion;
  const double value = preferred >= rule.finest && preferred <= rule.loosest
                           ? preferred
                           : rule.value / rule.companion;
  Companion companion = companion_at(rule, options, value);
  if (value < rule.value) {
    // a finer companion takes more steps than the run: as many more are allowed (1 / r for
    // delta_p, 5^(1/5) = 1.4 for a fifth-order step at a fifth of the tolerance, with room)
    const double more =
        rule.kind == StepRule::Kind::delta_p || rule.kind == StepRule::Kind::relative_delta_p
            ? rule.value / value
            : kFinerCompanionSteps;
    for (std::int64_t* max_steps : {&companion.options.impact.impulse_steps.max_steps,
                                    &companion.options.compliant.max_steps})
      *max_steps = std::int64_t(std::min(std::ceil(double(*max_steps) * more), 9e18));
  }
  return companion;
}

StepOptions first_step(const ContactModel& model, Method method, const StepOptions& options,
                       double accuracy) {
  StepOptions first = options;
  first.impact.delta_p.reset();
  first.impact.relative_delta_p.reset();
  const bool moving = model.beads && options.compliant.geometry != Geometry::frozen;
  const double chain_length =
      model.dimension == 1 ? std::min(1.0, kChainBodies / double(model.body_count())) : 1.0;
  if (method == Method::compliant)
    first.compliant.tolerance = accuracy * (moving ? kFirstMovingTolerance : chain_length);
  else if (options.impact.chosen_integrator() == plugins::LzbIntegrator::adaptive)
    first.impact.tolerance = accuracy * chain_length;
  else
    first.impact.delta_p =
        std::clamp(kFirstDeltaP * accuracy, kFinestFirstDeltaP, kCoarsestFirstDeltaP) *
        smallest_momentum(model);
  const StepRule rule = step_rule(model, method, first);
  return rule.at(first, std::clamp(rule.value, rule.finest, rule.loosest));
}

double observed_order(double step_before, double estimate_before, double step, double estimate) {
  const double order = std::log(estimate_before / estimate) / std::log(step_before / step);
  return std::isfinite(order) ? std::clamp(order, kLeastOrder, 1.0) : kLeastOrder;
}

double next_step(const StepRule& rule, double estimate, double accuracy, std::int64_t steps,
                 double order) {
  const bool tolerance = rule.kind == StepRule::Kind::lzb_tolerance ||
                         rule.kind == StepRule::Kind::compliant_tolerance;
  double aimed =
      rule.value *
      std::pow((accuracy / estimate) * (tolerance ? kToleranceAim : kDeltaPAim), 1.0 / order);
  // a coarser companion is the run before: at least that much coarser
  if (rule.companion > 1.0) aimed = std::min(aimed, rule.value / rule.companion);
  if (tolerance) return std::max(rule.finest, aimed);
  const double needed = double(steps) * rule.value / aimed;  // steps go as 1 / delta_p
  if (!(needed <= double(rule.max_steps)))
    fail_finer_than_allowed(accuracy, aimed, needed, rule.max_steps);
  return aimed;
}

nlohmann::ordered_json accuracy_json(const AccuracyRun& accuracy) {
  return {
      {"asked", accuracy.asked},
      {"met", accuracy.met},
      {"runs", accuracy.runs},
      {accuracy.step, accuracy.value},
      {"ended", accuracy.met ? nlohmann::ordered_json() : nlohmann::ordered_json(accuracy.ended)}};
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
