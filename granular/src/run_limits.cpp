#include "mimpact/granular/run_limits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "mimpact/common/error.hpp"

namespace mimpact::granular {

namespace {

// "1.2 GB", "850 MB", to `digits` significant digits
std::string size_text(double bytes, int digits) {
  const bool giga = bytes >= 1e9;
  char number[40];
  std::snprintf(number, sizeof number, "%.*g", digits, bytes / (giga ? 1e9 : 1e6));
  return std::string(number) + (giga ? " GB" : " MB");
}

}  // namespace

void RunLimits::check() const {
  if (!(memory_gb > 0.0 && std::isfinite(memory_gb)))
    throw InvalidInput(invalid_value_message(memory_option, memory_gb, "> 0 (GB), finite"));
  if (!(seconds > 0.0))
    throw InvalidInput(
        invalid_value_message(seconds_option, seconds, "> 0 (s); default: no limit"));
  if (threads != 1 && threads != 2)
    throw InvalidInput(invalid_value_message(
        threads_option, threads,
        "1 (an error estimate's companion after the run) or 2 (beside it; the default)"));
}

double model_bytes(double bodies, double contacts, int dimension) {
  return 1000.0 * double(dimension) * (bodies + contacts);
}

void check_memory(double bytes, const std::string& what, const RunLimits& limits) {
  if (!(bytes > limits.memory_bytes())) return;
  int digits = 3;  // as many as tell the need from the limit
  while (digits < 17 && size_text(bytes, digits) == size_text(limits.memory_bytes(), digits))
    ++digits;
  throw InvalidInput(what + " needs about " + size_text(bytes, digits) +
                     " of memory; allowed: at most " + size_text(limits.memory_bytes(), digits) +
                     " (raise the limit with " + limits.memory_option + ", in GB)");
}

double impact_duration_bound(const ContactModel& model) {
  double shortest = INFINITY;
  for (Eigen::Index j = 0; j < model.contact_count(); ++j) {
    const double u = model.u_minus(j);
    if (!(u < 0.0)) continue;
    const numerics::ContactLaw& law = model.laws[std::size_t(j)];
    const double a = 1.0 / (1.0 + law.exponent);
    const double quarter_period =
        std::sqrt(std::numbers::pi) * std::tgamma(1.0 + a) / std::tgamma(0.5 + a);
    const double reduced_mass = 1.0 / model.H.coeff(j, j);
    const double overlap =
        std::pow((1.0 + law.exponent) * reduced_mass * u * u / (2.0 * law.stiffness), a);
    shortest = std::min(shortest, quarter_period * overlap / -u);
  }
  return std::isfinite(shortest) ? shortest : 0.0;
}

RecordingBudget::RecordingBudget(double sample_bytes, double frame_bytes, const RunLimits& limits,
                                 std::string fields)
    : sample_bytes_(sample_bytes),
      frame_bytes_(frame_bytes),
      limits_(limits),
      fields_(std::move(fields)) {}

void RecordingBudget::check_estimate(double samples, double frames) const {
  check_memory(samples * sample_bytes_ + frames * frame_bytes_,
               "the recording (" + fields_ + ": at least " + rounded_text(samples) + " samples" +
                   (frames > 0.0 ? ", " + rounded_text(frames) + " frames" : "") + ")",
               limits_);
}

void RecordingBudget::add(bool frame) {
  kept_ += sample_bytes_ + (frame ? frame_bytes_ : 0.0);
  if (kept_ > limits_.memory_bytes())
    check_memory(kept_, "the recording (" + fields_ + ") outgrew its estimate: it", limits_);
}

}  // namespace mimpact::granular
