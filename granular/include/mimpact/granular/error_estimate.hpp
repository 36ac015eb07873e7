#pragma once

#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "mimpact/granular/contact_model.hpp"
#include "mimpact/granular/scene_spec.hpp"
#include "mimpact/plugins/lzb_impact_options.hpp"

// A run's estimate of its own answer's error, from a companion run of the same scene at another
// step (docs/design/error_estimates.md): the impulse steps are first order in delta_p, the
// adaptive LZB's and the compliant method's global error about proportional to their tolerance,
// so that error(k) ~ |v(k) - v(r k)| / |r - 1| (Richardson), times a safety factor that the
// measured ratios call for.
namespace mimpact::granular {

struct ErrorEstimate {
  // over the bodies, of the norm of each body's velocity error after the impact (or at
  // end_time), divided by the fastest body's speed before it
  double rms = 0.0;
  double worst = 0.0;
  std::string method;              // how it was estimated, in words
  double companion_seconds = 0.0;  // the companion run's wall time (s)
};

// The companion of a run: its step rule, and how its difference scales to the run's error.
struct Companion {
  plugins::LzbImpactOptions impact;  // the LZB method's options, at the companion's step
  CompliantSpec compliant;           // the compliant method's, at the companion's tolerance
  double scale = 1.0;                // error = scale x |v - v_companion|, per body
  std::string method;
};

// The companion of a run by `method` with the resolved `impact` options and `compliant` spec:
// twice delta_p (or half, where twice leaves its range), scale 2 / |r - 1|; ten times the
// tolerance (or a tenth, where ten times leaves the range of `frozen` integration), scale
// 3 / |r - 1|.
Companion companion_of(const ContactModel& model, Method method,
                       const plugins::LzbImpactOptions& impact, const CompliantSpec& compliant);

// The estimate from the run's and its companion's velocities (per coordinate, as
// ImpactOutcome::velocity_after).
ErrorEstimate estimate_error(const ContactModel& model, const Eigen::VectorXd& velocity,
                             const Eigen::VectorXd& companion_velocity, const Companion& companion);

// summary.json's "error_estimate": {"rms", "worst", "method", "companion_seconds"}, or null
// where the run made none.
nlohmann::ordered_json error_estimate_json(const std::optional<ErrorEstimate>& estimate);

}  // namespace mimpact::granular
