#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "mimpact/granular/contact_model.hpp"
#include "mimpact/granular/scene_spec.hpp"
#include "mimpact/plugins/lzb_impact_options.hpp"

// A run's estimate of its own answer's error, from a companion run of the same scene at another
// step (docs/design/error_estimates.md): the impulse steps are first order in delta_p, so that
// error(k) ~ |v(k) - v(2 k)| (Richardson); the adaptive LZB's and the compliant method's global
// error follows their tolerance too loosely for a coarser run to tell it, so their companion
// runs at a fifth of it, whose error is a fifth to a half of the run's: error(k) ~
// |v(k) - v(k / 5)| / 0.8. Each times a safety factor that the measured ratios call for.
namespace mimpact::granular {

struct ErrorEstimate {
  // over the bodies, of the norm of each body's velocity error after the impact (or at
  // end_time), divided by the fastest body's speed before it
  double rms = 0.0;
  double worst = 0.0;
  std::string method;              // how it was estimated, in words
  double companion_seconds = 0.0;  // the companion run's wall time (s)
};

// The step options of a run: the LZB method's and the compliant method's.
struct StepOptions {
  plugins::LzbImpactOptions impact;
  CompliantSpec compliant;
};

// The one number a run's error follows, k: delta_p (N s), relative_delta_p, or a tolerance.
struct StepRule {
  enum class Kind { delta_p, relative_delta_p, lzb_tolerance, compliant_tolerance };
  Kind kind = Kind::delta_p;
  double value = 0.0;          // the run's k
  double finest = 0.0;         // the smallest k the field allows
  double loosest = 0.0;        // the largest
  std::int64_t max_steps = 0;  // the impulse steps' budget
  // error(k) = safety |v(k) - v(r k)| / |r - 1|, for a finer companion (r < 1) and a coarser
  double finer_safety = 1.0;
  double coarser_safety = 1.0;
  double companion = 1.0;  // r of a run's companion (2 or 0.2), where the range allows
  std::string name;        // "delta_p", "tolerance"

  // `options` with k = value.
  StepOptions at(const StepOptions& options, double value) const;
};

// The step rule of a run by `method` with the resolved options.
StepRule step_rule(const ContactModel& model, Method method, const StepOptions& options);

// The companion of a run: its step options, and how its difference scales to the run's error.
struct Companion {
  StepOptions options;
  double scale = 1.0;  // error = scale x |v - v_companion|, per body
  std::string method;
  bool finer = false;  // its step is finer than the run's: it takes the longer
};

// The companion of a run at `rule.value` from a run at `value`: scale safety / |r - 1| with
// r = value / rule.value.
Companion companion_at(const StepRule& rule, const StepOptions& options, double value);
// The run's own companion: r = rule.companion, twice delta_p (or half, where twice leaves its
// range: then with twice the steps allowed); a fifth of the tolerance (or five times it, where a
// fifth leaves its range).
Companion companion_of(const StepRule& rule, const StepOptions& options);

// The estimate from the run's and its companion's velocities (per coordinate, as
// ImpactOutcome::velocity_after).
ErrorEstimate estimate_error(const ContactModel& model, const Eigen::VectorXd& velocity,
                             const Eigen::VectorXd& companion_velocity, const Companion& companion);

// A run asked for an accuracy (of the answer, as ErrorEstimate::worst): how it met it.
struct AccuracyRun {
  double asked = 0.0;
  bool met = false;    // the estimate's worst body is within it
  int runs = 0;        // of the scene begun, the answer's and its companions'
  std::string step;    // the step rule's field: "delta_p" (N s) or "tolerance"
  double value = 0.0;  // the answer's
  // where not met: what ended the runs first (the step's range, the most runs, or a finer run's
  // budget of steps, with its message)
  std::string ended;
};

// The step options of a first run asked for `accuracy` (docs/design/error_estimates.md,
// "Accuracy"): a tolerance of the accuracy (ten times it in the moving geometry, and the
// accuracy x 100 / bodies on a chain longer than 100 bodies); delta_p of
// kFirstDeltaP x the accuracy's share of the striker's momentum, coarse, so that its pair
// predicts the step at little cost.
StepOptions first_step(const ContactModel& model, Method method, const StepOptions& options,
                       double accuracy);
// The order q of the error in the step (error ~ k^q) between two runs' estimates, within
// [0.5, 1]: 0.5 where the error did not fall (docs/design/error_estimates.md, "Accuracy").
double observed_order(double step_before, double estimate_before, double step, double estimate);
// The next k of a run whose estimate at rule.value was `estimate` (> accuracy) in `steps`: the
// error taken as k^order, aimed below the accuracy, at least rule.companion times finer where
// the companion is coarser (the run before is the next one's), a tolerance at least
// rule.finest. Throws InvalidInput, naming the accuracy, for an impulse
// step whose steps (as 1 / delta_p) would pass impact.max_steps.
double next_step(const StepRule& rule, double estimate, double accuracy, std::int64_t steps,
                 double order = 1.0);

// summary.json's "accuracy": {"asked", "met", "runs", and the step rule's field}.
nlohmann::ordered_json accuracy_json(const AccuracyRun& accuracy);

// summary.json's "error_estimate": {"rms", "worst", "method", "companion_seconds"}, or null
// where the run made none.
nlohmann::ordered_json error_estimate_json(const std::optional<ErrorEstimate>& estimate);

}  // namespace mimpact::granular
