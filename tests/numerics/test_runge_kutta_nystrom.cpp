#include "mimpact/numerics/runge_kutta_nystrom.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

// The Runge-Kutta-Nystrom pair of the moving geometry on problems with known solutions: its
// order, its dense output against the exact motion, its peaks of a rate within a step, and its
// error control on an eccentric orbit.
namespace mimpact::numerics {
namespace {

using State = RungeKuttaNystrom::State;

// x'' = -x in the state's units of the moving geometry: y = (x, w = T x', q = integral of x),
// x' = w / T, w' = -T x, q' = x; exactly x = cos t, w = -T sin t, q = sin t from (1, 0, 0).
constexpr double kTimeScale = 3.0;
void oscillator(const State& y, State& dydt, double) {
  dydt[1] = -kTimeScale * y[0];
  dydt[2] = y[0];
}

RungeKuttaNystrom fixed_steps(double h) {
  OdeOptions options;
  options.absolute_tolerance = 1e300;  // never rejects: every step is max_step
  options.relative_tolerance = 0.0;
  options.max_step = h;
  return RungeKuttaNystrom(options);
}

// The largest error of the three components at t = 1 after steps of h.
double error_after_steps(double h) {
  RungeKuttaNystrom rkn = fixed_steps(h);
  rkn.restart({1.0, 0.0, 0.0}, 0.0, h, 1, 1.0 / kTimeScale);
  while (rkn.time() < 1.0 - 1e-12) rkn.step(oscillator);
  const State& y = rkn.state();
  const double t = rkn.time();
  return std::max({std::abs(y[0] - std::cos(t)), std::abs(y[1] / kTimeScale + std::sin(t)),
                   std::abs(y[2] - std::sin(t))});
}

TEST(RungeKuttaNystrom, IsOfOrderFourOnTheOscillator) {
  // the global error falls as h^4: log2 of the ratio between h and h/2 near 4
  for (double h : {0.1, 0.05, 0.025}) {
    const double order = std::log2(error_after_steps(h) / error_after_steps(h / 2));
    EXPECT_NEAR(order, 4.0, 0.15) << "h = " << h;
  }
}

TEST(RungeKuttaNystrom, DenseOutputFollowsTheMotionWithinAStep) {
  // within one step from the exact state: x (the quintic Hermite) and w (its derivative) O(h^5)
  // off, as the step's end; q (a cubic Hermite) O(h^4)
  auto worst_inside = [](double h) {
    RungeKuttaNystrom rkn = fixed_steps(h);
    rkn.restart({1.0, 0.0, 0.0}, 0.0, h, 1, 1.0 / kTimeScale);
    rkn.step(oscillator);
    std::array<double, 3> worst{};
    State y;
    for (double theta : {0.1, 0.3, 0.5, 0.7, 0.9}) {
      const double t = theta * h;
      rkn.state_at(t, y);
      const RungeKuttaNystrom::Weights w = rkn.weights_at(t);
      for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(rkn.component_at(w, i), y[i]);
      worst[0] = std::max(worst[0], std::abs(y[0] - std::cos(t)));
      worst[1] = std::max(worst[1], std::abs(y[1] / kTimeScale + std::sin(t)));
      worst[2] = std::max(worst[2], std::abs(y[2] - std::sin(t)));
    }
    return worst;
  };
  const auto coarse = worst_inside(0.2), fine = worst_inside(0.1);
  EXPECT_GT(std::log2(coarse[0] / fine[0]), 4.8);  // x: O(h^5)
  EXPECT_GT(std::log2(coarse[1] / fine[1]), 4.7);  // w: O(h^5)
  EXPECT_GT(std::log2(coarse[2] / fine[2]), 3.8);  // q: O(h^4)
  EXPECT_LT(fine[0], 1e-7);
}

// The Kepler problem, eccentricity 0.8 (GM = 1, a = 1: period 2 pi), in the moving geometry's
// layout: (x, y, w_x, w_y, impulse of the x force) with kappa = 1.
void kepler(const State& y, State& dydt, double) {
  const double r2 = y[0] * y[0] + y[1] * y[1];
  const double inverse_r3 = 1.0 / (r2 * std::sqrt(r2));
  dydt[2] = -y[0] * inverse_r3;
  dydt[3] = -y[1] * inverse_r3;
  dydt[4] = dydt[2];
}

TEST(RungeKuttaNystrom, ErrorControlClosesAnEccentricOrbit) {
  // from the pericentre (0.2, 0) at speed sqrt(1.8 / 0.2) = 3: after one period the body is back,
  // the error falling with the tolerance
  const double e = 0.8, start_speed = std::sqrt((1.0 + e) / (1.0 - e));
  double previous = 1.0;
  for (double tolerance : {1e-6, 1e-8, 1e-10}) {
    OdeOptions options;
    options.absolute_tolerance = options.relative_tolerance = tolerance;
    RungeKuttaNystrom rkn(options);
    rkn.restart({1.0 - e, 0.0, 0.0, start_speed, 0.0}, 0.0, 1e-3, 2, 1.0);
    const double period = 2.0 * std::numbers::pi;
    while (rkn.time() < period) {
      rkn.step(kepler);
      ASSERT_EQ(rkn.state()[4], rkn.state()[2]);  // q and w_x: the same sums of the same f
    }
    State y;
    rkn.state_at(period, y);
    const double error = std::hypot(y[0] - (1.0 - e), y[1]);
    EXPECT_LT(error, 20.0 * tolerance) << "tolerance " << tolerance;
    EXPECT_LT(error, previous / 20.0) << "tolerance " << tolerance;
    previous = error;
    EXPECT_LT(rkn.steps(), 8.0 * std::pow(tolerance, -0.25));  // 5.4 to 5.6 measured
  }
}

// rate_peak: the largest of q' = x = cos t over one step across its maximum at t = 0, from the
// cubic through the step's four stage values, against the exact 1 at 0; O(h^4) in the value
// (the stages' own errors and the cubic's), and the same floor honoured.
TEST(RungeKuttaNystrom, RatePeakFindsTheMaximumWithinAStepToOrderFour) {
  auto peak_error = [](double h) {
    RungeKuttaNystrom rkn = fixed_steps(h);
    const double t0 = -0.3 * h;
    rkn.restart({std::cos(t0), -kTimeScale * std::sin(t0), std::sin(t0)}, t0, h, 1,
                1.0 / kTimeScale);
    rkn.step(oscillator);
    const auto peak = rkn.rate_peak(2, t0, t0 + h, 0.0);
    EXPECT_NEAR(peak.time, 0.0, 0.01 * h);
    // a segment ending before the maximum: its end, the cubic there
    const auto before = rkn.rate_peak(2, t0, -0.1 * h, 0.0);
    EXPECT_NEAR(before.value, std::cos(0.1 * h), 1e-3 * h * h);
    EXPECT_DOUBLE_EQ(before.time, -0.1 * h);
    // nothing above a floor the cubic cannot reach
    EXPECT_TRUE(std::isnan(rkn.rate_peak(2, t0, t0 + h, 1.6).time));
    return std::abs(peak.value - 1.0);
  };
  for (double h : {0.4, 0.2, 0.1}) {
    const double order = std::log2(peak_error(h) / peak_error(h / 2));
    std::printf("h = %.2f: peak error %.3e, order %.2f\n", h, peak_error(h), order);
    EXPECT_GT(order, 3.8) << "h = " << h;
  }
}

}  // namespace
}  // namespace mimpact::numerics
