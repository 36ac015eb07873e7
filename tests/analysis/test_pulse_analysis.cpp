// Pulse measures of Nguyen & Brogliato (2011) (eqs. 40-43) on pulses whose answers are known.
#include "mimpact/analysis/pulse_analysis.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mimpact/common/error.hpp"

namespace mimpact::analysis {
namespace {

// the antiderivative of cos^6
double cos6_integral(double u) {
  return 5.0 * u / 16.0 + 15.0 * std::sin(2 * u) / 64.0 + 3.0 * std::sin(4 * u) / 64.0 +
         std::sin(6 * u) / 192.0;
}

struct Record {
  std::vector<double> time, force;
};

Record cos6_record(double peak, double center, double width, double step, double tail = 0.0) {
  Record record;
  for (double t = 0.0; t <= center + 3.0 * width; t += step) {
    const double phase = (t - center) / width;
    double f = std::abs(phase) < std::numbers::pi / 2 ? peak * std::pow(std::cos(phase), 6) : 0.0;
    if (phase > 1.5) f += tail;  // a constant tail behind the pulse
    record.time.push_back(t);
    record.force.push_back(f);
  }
  return record;
}

TEST(PulseAnalysis, RecoversACos6Pulse) {
  const double peak = 25.0, center = 8e-4, width = 1.1e-4;
  const Record record = cos6_record(peak, center, width, 1e-7);
  const PulseMeasures pulse = measure_pulse(record.time, record.force);
  EXPECT_DOUBLE_EQ(pulse.peak, peak);
  EXPECT_NEAR(pulse.time_of_peak, center, 1e-7);
  EXPECT_NEAR(pulse.width, width, 1e-4 * width);
  // P_F = F_m tau (I(1) - I(-pi/2)), P_T = F_m tau (I(pi/2) - I(1))
  const double front = peak * width * (cos6_integral(1.0) - cos6_integral(-std::numbers::pi / 2));
  const double tail = peak * width * (cos6_integral(std::numbers::pi / 2) - cos6_integral(1.0));
  EXPECT_NEAR(pulse.front_impulse, front, 1e-4 * front);
  EXPECT_NEAR(pulse.tail_impulse, tail, 1e-2 * tail);
  EXPECT_NEAR(front / (peak * width), 0.9796,
              1e-4);  // as quoted for Nguyen & Brogliato's definitions
}

TEST(PulseAnalysis, TheFitUsesTheFrontOnly) {
  // a long tail behind the peak changes P_T, not tau
  const double peak = 10.0, center = 5e-4, width = 8e-5;
  const Record record = cos6_record(peak, center, width, 1e-7, 0.5);
  const PulseMeasures pulse = measure_pulse(record.time, record.force);
  EXPECT_NEAR(pulse.width, width, 1e-4 * width);
  const double tail_time = record.time.back() - (center + 1.5 * width);
  EXPECT_GT(pulse.tail_impulse, 0.5 * tail_time);
}

TEST(PulseAnalysis, WindowSelectsAPulse) {
  Record record = cos6_record(10.0, 2e-4, 3e-5, 1e-7);
  const Record second = cos6_record(20.0, 2e-4, 3e-5, 1e-7);
  const double shift = record.time.back() + 1e-7;
  for (std::size_t k = 0; k < second.time.size(); ++k) {
    record.time.push_back(shift + second.time[k]);
    record.force.push_back(second.force[k]);
  }
  EXPECT_DOUBLE_EQ(measure_pulse(record.time, record.force).peak, 20.0);
  EXPECT_DOUBLE_EQ(measure_pulse(record.time, record.force, 0.0, shift).peak, 10.0);
}

TEST(PulseAnalysis, WaveSpeedAndBadRecords) {
  EXPECT_DOUBLE_EQ(wave_speed(0.026, 1e-4, 1.26e-4), 1000.0);
  EXPECT_THROW(wave_speed(0.026, 2e-4, 1e-4), InvalidInput);
  const std::vector<double> t{0.0, 1.0}, f{0.0};
  EXPECT_THROW(measure_pulse(t, f), InvalidInput);
  const std::vector<double> zero{0.0, 0.0};
  EXPECT_THROW(measure_pulse(t, zero), InvalidInput);
  const std::vector<double> backwards{1.0, 0.0}, some{1.0, 2.0};
  EXPECT_THROW(measure_pulse(backwards, some), InvalidInput);
}

TEST(PulseAnalysis, FindsEachPulseOfATrain) {
  // five pulses of falling height, separated by gaps, then noise below the threshold
  Record train;
  double t0 = 0.0;
  for (double peak : {60.0, 40.0, 25.0, 17.0, 11.0, 1.0, 0.5}) {
    const Record pulse = cos6_record(peak, 1e-4, 2e-5, 1e-6);
    for (std::size_t k = 0; k < pulse.time.size(); ++k) {
      train.time.push_back(t0 + pulse.time[k]);
      train.force.push_back(pulse.force[k]);
    }
    t0 = train.time.back() + 1e-6;
  }
  const std::vector<Peak> pulses = find_pulses(train.time, train.force, 3.0);
  ASSERT_EQ(pulses.size(), 5u);
  EXPECT_DOUBLE_EQ(pulses[0].force, 60.0);
  EXPECT_DOUBLE_EQ(pulses[4].force, 11.0);
  for (std::size_t k = 1; k < pulses.size(); ++k) EXPECT_GT(pulses[k].time, pulses[k - 1].time);
}

}  // namespace
}  // namespace mimpact::analysis
