#include "mimpact/analysis/pulse_analysis.hpp"

#include <algorithm>
#include <boost/math/tools/minima.hpp>
#include <cmath>
#include <numbers>
#include <string>

#include "mimpact/common/error.hpp"

namespace mimpact::analysis {

namespace {

double cos6_pulse(double peak, double center, double width, double t) {
  const double phase = (t - center) / width;
  if (std::abs(phase) >= std::numbers::pi / 2) return 0.0;
  const double c = std::cos(phase);
  const double c2 = c * c;
  return peak * c2 * c2 * c2;
}

// The integral of the linear interpolant of (time, force) over [from, to].
double trapezoid(std::span<const double> time, std::span<const double> force, double from,
                 double to) {
  double total = 0.0;
  for (std::size_t k = 1; k < time.size(); ++k) {
    const double a = std::max(time[k - 1], from), b = std::min(time[k], to);
    if (b <= a) continue;
    const double span = time[k] - time[k - 1];
    auto at = [&](double t) {
      return force[k - 1] + (force[k] - force[k - 1]) * (t - time[k - 1]) / span;
    };
    total += 0.5 * (at(a) + at(b)) * (b - a);
  }
  return total;
}

}  // namespace

PulseMeasures measure_pulse(std::span<const double> time, std::span<const double> force,
                            double begin, double end) {
  if (time.size() != force.size())
    throw InvalidInput("measure_pulse: " + std::to_string(time.size()) + " times but " +
                       std::to_string(force.size()) + " forces; allowed: one force per time");
  for (std::size_t k = 1; k < time.size(); ++k)
    if (!(time[k] >= time[k - 1]))
      throw InvalidInput("measure_pulse: time[" + std::to_string(k) + "] = " + to_text(time[k]) +
                         " comes before time[" + std::to_string(k - 1) +
                         "]; allowed: increasing times");
  std::size_t top = time.size();
  for (std::size_t k = 0; k < time.size(); ++k)
    if (time[k] >= begin && time[k] <= end && (top == time.size() || force[k] > force[top]))
      top = k;
  if (top == time.size() || !(force[top] > 0.0))
    throw InvalidInput("measure_pulse: no positive force in [" + to_text(begin) + ", " +
                       to_text(end) + "] s");

  PulseMeasures pulse;
  pulse.peak = force[top];
  pulse.time_of_peak = time[top];
  std::size_t first = top;
  while (first > 0 && force[first - 1] > 0.0 && time[first - 1] >= begin) --first;
  // the front: from the last zero force before the peak up to the peak
  const std::size_t onset = first > 0 ? first - 1 : first;
  const double rise = pulse.time_of_peak - time[onset];
  auto misfit = [&](double width) {
    double sum = 0.0;
    for (std::size_t k = onset; k <= top; ++k) {
      const double r = force[k] - cos6_pulse(pulse.peak, pulse.time_of_peak, width, time[k]);
      sum += r * r;
    }
    return sum;
  };
  if (rise > 0.0) {
    // the front lasts pi tau / 2 for a pure cos^6; search well around that
    const double guess = 2.0 * rise / std::numbers::pi;
    pulse.width =
        boost::math::tools::brent_find_minima(misfit, 0.05 * guess, 20.0 * guess, 40).first;
  }
  const double split = pulse.time_of_peak + pulse.width;
  pulse.front_impulse = trapezoid(time, force, begin, std::min(split, end));
  pulse.tail_impulse = trapezoid(time, force, split, end);
  return pulse;
}

double wave_speed(double diameter, double time_left, double time_right) {
  if (!(time_right > time_left))
    throw InvalidInput("wave_speed: the right contact's time " + to_text(time_right) +
                       " s is not after the left one's " + to_text(time_left) + " s");
  return diameter / (time_right - time_left);
}

std::vector<Peak> find_pulses(std::span<const double> time, std::span<const double> force,
                              double threshold) {
  std::vector<Peak> pulses;
  double trough = INFINITY;  // lowest force since the last kept pulse
  for (std::size_t k = 1; k + 1 < force.size(); ++k) {
    trough = std::min(trough, force[k]);
    const bool local_maximum = force[k] > force[k - 1] && force[k] >= force[k + 1];
    if (!local_maximum || force[k] < threshold) continue;
    if (!pulses.empty() && trough > 0.5 * std::min(pulses.back().force, force[k])) {
      if (force[k] > pulses.back().force) pulses.back() = {time[k], force[k]};  // same pulse
    } else {
      pulses.push_back({time[k], force[k]});
    }
    trough = force[k];
  }
  return pulses;
}

}  // namespace mimpact::analysis
