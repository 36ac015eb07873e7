#include "mimpact/granular/configuration_check.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "mimpact/common/error.hpp"
#include "mimpact/granular/scene_spec.hpp"

namespace mimpact::granular {

namespace {

// The check's budget: the moving geometry may carry bodies over this many steps for every
// contact step of the LZB run (ordinary scenes take 0.4 to 2.1: docs/limits.md), and at least
// kLeastBodySteps (about 0.1 s).
constexpr std::int64_t kWorkShare = 3;
constexpr std::int64_t kLeastBodySteps = 100'000;

std::string short_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

// Why the moving geometry cannot take the model's contacts, or nothing: a restitution below
// kLeastCompliantRestitution, or friction on inelastic contacts (MovingContacts).
std::string what_the_moving_geometry_refuses(const ContactModel& model) {
  for (const numerics::ContactLaw& law : model.laws) {
    if (law.restitution < kLeastCompliantRestitution)
      return "the moving geometry takes restitution >= " + short_text(kLeastCompliantRestitution) +
             " in a packing, and it is " + short_text(law.restitution) +
             " here (below it the beads' outcome as they move is ill-conditioned)";
    if (law.friction > 0.0 && law.effective_restitution() < 1.0)
      return "the moving geometry takes friction on elastic contacts only (restitution 1), and "
             "the restitution is " +
             short_text(law.restitution) + " here";
  }
  return {};
}

}  // namespace

std::string ConfigurationCheck::describe() const {
  if (!not_made.empty())
    return "the LZB impact keeps the configuration of the impact, and its check against the "
           "beads as they move could not be made: " +
           not_made;
  std::string line =
      "the LZB impact keeps the configuration of the impact; the beads as they move "
      "(compliant contacts in the moving geometry, tolerance " +
      short_text(tolerance) + ") differ from it at t = " + short_text(time) + " s by RMS " +
      short_text(rms_error) + " and at worst " + short_text(worst_error) + " (body " +
      std::to_string(worst_body) + ") of the striker's speed";
  if (holds()) return line + ", within the accuracy " + short_text(accuracy);
  line += ", beyond the accuracy " + short_text(accuracy) +
          " (configuration_check.accuracy): the scene needs \"method\": \"compliant\", which "
          "follows the beads as they move";
  return line;
}

ConfigurationCheck check_configuration(const ContactModel& model, const ImpactOutcome& lzb,
                                       const ConfigurationCheckSpec& spec, double default_accuracy,
                                       const RunLimits& limits, ProgressMeter* progress) {
  if (!model.beads) throw Error("configuration check: the model has no beads to move");
  ConfigurationCheck check;
  check.accuracy = spec.accuracy.value_or(default_accuracy);
  check.tolerance = spec.tolerance.value_or(std::clamp(1e-2 * check.accuracy, 1e-10, 1e-4));
  check.time = lzb.impact_time + lzb.result.duration;
  const int d = model.dimension;
  const Eigen::Index bodies = model.body_count();
  for (Eigen::Index b = 0; b < bodies; ++b)
    check.speed = std::max(check.speed, model.velocity.segment(b * d, d).norm());

  check.not_made = what_the_moving_geometry_refuses(model);
  if (!check.not_made.empty()) return check;
  CompliantSpec moving;
  moving.tolerance = check.tolerance;
  moving.end_time = check.time;
  moving.geometry = Geometry::moving;
  moving.max_body_steps = std::max(kLeastBodySteps, kWorkShare * lzb.result.contact_steps);
  const auto start = std::chrono::steady_clock::now();
  CompliantRun run;
  try {
    if (progress) progress->begin("configuration check", check.time);
    run = simulate_compliant(model, nullptr, moving, {.limits = limits, .progress = progress});
  } catch (const TimeLimitReached&) {  // the caller's limit, not the check's budget
    throw;
  } catch (const BudgetSpent& spent) {
    check.not_made = "the moving geometry would take more than " + std::to_string(kWorkShare) +
                     " times the LZB run's work (" + std::to_string(moving.max_body_steps) +
                     " body steps): it had reached t = " + short_text(spent.time()) + " s of " +
                     short_text(check.time) +
                     " s; a coarser configuration_check.tolerance costs less, and "
                     "configuration_check.enabled false skips the check";
    return check;
  } catch (const Error& error) {
    check.not_made = error.what();
    return check;
  }
  check.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  double squares = 0.0;
  for (Eigen::Index b = 0; b < bodies; ++b) {
    const double difference =
        (lzb.velocity_after.segment(b * d, d) - run.impact.velocity_after.segment(b * d, d))
            .norm() /
        check.speed;
    squares += difference * difference;
    if (difference > check.worst_error) {
      check.worst_error = difference;
      check.worst_body = b;
    }
  }
  check.rms_error = std::sqrt(squares / double(bodies));
  return check;
}

}  // namespace mimpact::granular
