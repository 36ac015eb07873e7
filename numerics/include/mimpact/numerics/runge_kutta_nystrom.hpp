#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

#include "mimpact/numerics/embedded_pair.hpp"
#include "mimpact/numerics/ode_options.hpp"

namespace mimpact::numerics {

// The embedded Runge-Kutta-Nystrom pair RKN4(3)4FM of Dormand, El-Mikkawy & Prince (IMA J.
// Numer. Anal. 7, 1987, table 3) with error control and dense output, for a flat state
// y = (x, w, q) whose accelerations depend on the positions alone:
//   x' = kappa w,   w' = f(x),   q' = g(x)
// (q: integrals of the forces, which no derivative reads). A Nystrom step forms the stages'
// positions only, and its four stages share the last with the next step's first: three
// evaluations of f a step where Dormand-Prince 5(4) takes six (Hairer, Norsett & Wanner,
// Solving ODEs I, section II.14). Between the step's ends the state is the quintic Hermite of
// x (its values, rates and accelerations at both ends, error O(h^6)), its derivative for w, and
// the cubic Hermite of q.
class RungeKuttaNystrom : public EmbeddedPair<RungeKuttaNystrom> {
 public:
  explicit RungeKuttaNystrom(const OdeOptions& options)
      : EmbeddedPair("Runge-Kutta-Nystrom", options.absolute_tolerance, options.relative_tolerance,
                     options.max_step) {}

  // Starts again from (t, y) with a first step of `first_step`: y's first `positions`
  // components are x, the next as many w (x' = velocity_scale w), the rest q. The steps
  // (step(), inherited) take rhs(y, dydt, t), which writes dydt's w and q parts from y's x part.
  // An rhs that also has amend(y0, dydt0, y1, dydt1, h, switching) is handed every attempted
  // step's end y1 to amend, with the derivatives at both ends (dydt1 at y1 as the step formed
  // it) and the q components whose rates switched on or off within the step (zero at some of
  // its stages, not at others): a contact force that began or ended there, whose quadrature
  // the rhs may correct (onset_quadrature.hpp). The error estimate is the unamended pair's.
  // An amend that returns a double may ask for a shorter step instead: a share of h below 1
  // rejects the attempt and tries that share of it next (a law that changes too sharply within
  // the step to amend, which the shorter step ends just after). `last_error` is the step-size
  // controller's memory, the error ratio of the last step accepted (after_acceptance): kNoLastError
  // where the motion starts afresh, or last_error() where it goes on.
  static constexpr double kNoLastError = 1e-4;  // Hairer's start
  void restart(const State& y, double t, double first_step, std::size_t positions,
               double velocity_scale, double last_error = kNoLastError) {
    start(y, t, first_step);
    for (State& k : stage_) k.resize(y.size());
    probe_ = y;
    positions_ = positions;
    kappa_ = velocity_scale;
    last_error_ = last_error;
    rejected_ = false;
    cut_to_ = 0.0;
  }
  double last_error() const { return last_error_; }

  // The Hermite bases at a time of the last step, for component_at.
  struct Weights {
    std::array<double, 6> position{};  // of x0, h x0', h^2 x0'', x1, h x1', h^2 x1''
    std::array<double, 6> rate{};      // their derivatives in theta
    std::array<double, 4> integral{};  // of q0, h q0', q1, h q1'
  };
  Weights weights_at(double t) const;
  double component_at(const Weights& w, std::size_t i) const { return interpolate(w, i); }

  // The largest value over [t0, t1] of the last step of a q component's rate g, a force's
  // magnitude (>= 0), if it exceeds `floor`: the cubic through g at the step's four nodes,
  // which the step evaluated (error O(h^4) where g is smooth, as the dense output's; no
  // evaluation of the right-hand side). Where g is zero at some nodes and not at others (a
  // force that switched on or off within the step, not smooth there) the largest node within
  // [t0, t1]. Nothing ({floor, NaN}) where no value can exceed the floor: the cubic is at most
  // its Lebesgue constant times its largest node on [0, 1].
  struct Peak {
    double value = 0.0, time = std::numeric_limits<double>::quiet_NaN();
  };
  Peak rate_peak(std::size_t i, double t0, double t1, double floor) const;

 private:
  friend class EmbeddedPair<RungeKuttaNystrom>;

  template <class Rhs>
  double attempt(Rhs& rhs, double h);
  // A rejected step shrinks by 0.9 err^(-1/4), at most fivefold (the error estimate is O(h^4)).
  // An accepted one changes by Gustafsson's proportional-integral rule (ACM TOMS 17, 1991), as
  // Hairer's DOPRI5 with beta = 0.08 (Hairer, Norsett & Wanner, Solving ODEs I, section II.4): 0.9
  // err^(-(1/4 - 0.75 beta)) err_last^beta within [1/5, 5], and not up right after a rejection;
  // the last error is carried across restarts (restart's last_error); against the rule without
  // its integral part, docs/design/moving_geometry.md. max_step bounds every step.
  bool admit(double& h) const {
    if (max_step_ > 0.0) h = std::min(h, max_step_);
    return true;
  }
  double after_rejection(double h, double error) {
    rejected_ = true;
    if (cut_to_ > 0.0) return std::exchange(cut_to_, 0.0);
    return h * std::max(0.9 * std::pow(error, -0.25), 0.2);
  }
  double after_acceptance(double h, double error) {
    constexpr double kBeta = 0.08, kExponent = 0.25 - 0.75 * kBeta;
    const double e = std::max(error, 1e-4);
    double next =
        h * std::clamp(0.9 * std::pow(e, -kExponent) * std::pow(last_error_, kBeta), 0.2, 5.0);
    if (rejected_) next = std::min(next, h);
    rejected_ = false;
    last_error_ = e;
    return next;
  }
  double interpolate(const Weights& w, std::size_t i) const;

  std::array<State, 2> stage_;          // f and g at the stages 2 and 3
  State probe_;                         // a stage's positions
  std::vector<std::size_t> switching_;  // of the q components, for amend (its first few)
  std::size_t positions_ = 0;
  double kappa_ = 1.0;
  double last_error_ = kNoLastError;  // of the last step accepted
  bool rejected_ = false;             // the last attempt was
  double cut_to_ = 0.0;               // s: the step its amend asked for, or 0
};

// RKN4(3)4FM: nodes c, stage weights a (for x''), the fourth-order weights b (x) and bp (w, q),
// the third-order ones e (x) and ep (w, q) given as their differences to the fourth.
namespace rkn43 {
constexpr double c2 = 1.0 / 4.0, c3 = 7.0 / 10.0;
constexpr double a21 = 1.0 / 32.0;
constexpr double a31 = 7.0 / 1000.0, a32 = 119.0 / 500.0;
constexpr double b1 = 1.0 / 14.0, b2 = 8.0 / 27.0, b3 = 25.0 / 189.0;  // b4 = 0: first same as last
constexpr double bp1 = 1.0 / 14.0, bp2 = 32.0 / 81.0, bp3 = 250.0 / 567.0, bp4 = 5.0 / 54.0;
constexpr double e1 = b1 - -7.0 / 150.0, e2 = b2 - 67.0 / 150.0, e3 = b3 - 3.0 / 20.0,
                 e4 = 0.0 - -1.0 / 20.0;
constexpr double ep1 = bp1 - 13.0 / 21.0, ep2 = bp2 - -20.0 / 27.0, ep3 = bp3 - 275.0 / 189.0,
                 ep4 = bp4 - -1.0 / 3.0;
constexpr std::array<double, 4> nodes{0.0, c2, c3, 1.0}, velocity_weights{bp1, bp2, bp3, bp4},
    position_weights{b1, b2, b3, 0.0};
}  // namespace rkn43

template <class Rhs>
double RungeKuttaNystrom::attempt(Rhs& rhs, double h) {
  using namespace rkn43;
  const State& y = y_[current_];
  const State& k1 = dydt_[current_];
  State& out = y_[1 - current_];
  // (a compensated sum, the increments' round-off carried to the next step, changed nothing
  // measurable: a line of beads against the chain 8.1e-13 without, 7.6e-13 with, and cost a
  // twentieth of a packing's run)
  auto add = [&](std::size_t i, double increment) { out[i] = y[i] + increment; };
  State& k4 = dydt_[1 - current_];
  auto& [k2, k3] = stage_;
  const std::size_t p = positions_, n = y.size();
  const double* w = y.data() + p;
  const double t = time_, hk = h * kappa_, hhk = h * hk;
  // x'' = kappa f: the stages' positions x + c h kappa w + h^2 kappa sum a f
  for (std::size_t i = 0; i < p; ++i) probe_[i] = y[i] + c2 * hk * w[i] + hhk * (a21 * k1[p + i]);
  rhs(probe_, k2, t + c2 * h);
  for (std::size_t i = 0; i < p; ++i)
    probe_[i] = y[i] + c3 * hk * w[i] + hhk * (a31 * k1[p + i] + a32 * k2[p + i]);
  rhs(probe_, k3, t + c3 * h);
  for (std::size_t i = 0; i < p; ++i)
    add(i, hk * w[i] + hhk * (b1 * k1[p + i] + b2 * k2[p + i] + b3 * k3[p + i]));
  rhs(out, k4, t + h);
  // the largest ratio of an error to its tolerance, divided out only where it may grow (the
  // margin of four roundings keeps every ratio that could): the same number as dividing every
  // component, where those divisions, each waiting on the last maximum, were half of the step's
  // own arithmetic
  double largest = 0.0;
  constexpr double kMargin = 1.0 - 4.0 * std::numeric_limits<double>::epsilon();
  auto hold = [&](std::size_t i, double error, double rate) {
    const double scale = absolute_ + relative_ * (std::abs(y[i]) + std::abs(h * rate));
    if (std::abs(error) >= kMargin * largest * scale)
      largest = std::max(largest, std::abs(error) / scale);
  };
  for (std::size_t i = 0; i < p; ++i)
    hold(i, hhk * (e1 * k1[p + i] + e2 * k2[p + i] + e3 * k3[p + i] + e4 * k4[p + i]),
         kappa_ * w[i]);
  constexpr bool kAmends =
      requires(Rhs & r, const State& a, State& b, double s, std::span<const std::size_t> i) {
    r.amend(a, a, b, a, s, i);
  };
  auto velocity_and_error = [&](std::size_t i) {
    add(i, h * (bp1 * k1[i] + bp2 * k2[i] + bp3 * k3[i] + bp4 * k4[i]));
    hold(i, h * (ep1 * k1[i] + ep2 * k2[i] + ep3 * k3[i] + ep4 * k4[i]), k1[i]);
  };
  for (std::size_t i = p; i < 2 * p; ++i) velocity_and_error(i);
  if constexpr (kAmends) {
    // the rates are the forces' magnitudes, >= 0: some zero and not all, written without a
    // branch (a switch is rare)
    if (switching_.size() < n - 2 * p) switching_.resize(n - 2 * p);
    std::size_t switched = 0;
    for (std::size_t i = 2 * p; i < n; ++i) {
      velocity_and_error(i);
      switching_[switched] = i - 2 * p;
      switched += (k1[i] * k2[i] * k3[i] * k4[i] == 0.0) & (k1[i] + k2[i] + k3[i] + k4[i] > 0.0);
    }
    const std::span<const std::size_t> switches(switching_.data(), switched);
    if constexpr (std::is_same_v<decltype(rhs.amend(y, k1, out, k4, h, switches)), double>) {
      const double share = rhs.amend(y, k1, out, k4, h, switches);
      if (share < 1.0) {
        cut_to_ = share * h;
        return std::numeric_limits<double>::infinity();
      }
    } else {
      rhs.amend(y, k1, out, k4, h, switches);
    }
  } else {
    for (std::size_t i = 2 * p; i < n; ++i) velocity_and_error(i);
  }
  return largest;
}

namespace rkn43 {
// the cubic through values at the nodes: its monomial coefficients are kCubic times the values
// (the inverse of the nodes' Vandermonde matrix), and on [0, 1] it is at most kLebesgue times
// the largest of them in magnitude (max over s of sum |l_i(s)|, 1.5179 at s = 0.469)
constexpr std::array<std::array<double, 4>, 4> kCubic = [] {
  std::array<std::array<double, 4>, 4> m{};
  for (std::size_t i = 0; i < 4; ++i) {
    // l_i(s) = prod_{k != i} (s - c_k) / (c_i - c_k), expanded
    std::array<double, 4> p{1.0, 0.0, 0.0, 0.0};
    double denominator = 1.0;
    for (std::size_t k = 0; k < 4; ++k) {
      if (k == i) continue;
      for (std::size_t j = 3; j > 0; --j) p[j] = p[j - 1] - nodes[k] * p[j];
      p[0] = -nodes[k] * p[0];
      denominator *= nodes[i] - nodes[k];
    }
    for (std::size_t j = 0; j < 4; ++j) m[j][i] = p[j] / denominator;
  }
  return m;
}();
constexpr double kLebesgue = 1.518;
}  // namespace rkn43

inline RungeKuttaNystrom::Peak RungeKuttaNystrom::rate_peak(std::size_t i, double t0, double t1,
                                                            double floor) const {
  using namespace rkn43;
  const std::array<double, 4> g{dydt_[1 - current_][i], stage_[0][i], stage_[1][i],
                                dydt_[current_][i]};
  const double largest = std::max(std::max(g[0], g[1]), std::max(g[2], g[3]));
  if (kLebesgue * largest <= floor) return {floor};
  const double h = time_ - previous_time_, s0 = (t0 - previous_time_) / h,
               s1 = (t1 - previous_time_) / h;
  Peak peak{floor};
  auto consider = [&](double s, double value) {
    if (value > peak.value) peak = {value, previous_time_ + s * h};
  };
  if (g[0] * g[1] * g[2] * g[3] == 0.0) {  // switched within the step
    for (std::size_t k = 0; k < 4; ++k)
      if (nodes[k] >= s0 && nodes[k] <= s1) consider(nodes[k], g[k]);
    return peak;
  }
  std::array<double, 4> a{};
  for (std::size_t j = 0; j < 4; ++j)
    a[j] = kCubic[j][0] * g[0] + kCubic[j][1] * g[1] + kCubic[j][2] * g[2] + kCubic[j][3] * g[3];
  auto cubic = [&](double s) { return a[0] + s * (a[1] + s * (a[2] + s * a[3])); };
  consider(s1, s1 == 1.0 ? g[3] : cubic(s1));
  // its maxima: a1 + 2 a2 s + 3 a3 s^2 = 0 where 2 a2 + 6 a3 s < 0
  const double A = 3.0 * a[3], B = 2.0 * a[2], C = a[1];
  const double discriminant = B * B - 4.0 * A * C;
  if (A == 0.0) {
    if (B < 0.0) {
      const double s = -C / B;
      if (s > s0 && s < s1) consider(s, cubic(s));
    }
  } else if (discriminant >= 0.0) {
    // the roots without cancellation; the maximum is the one where the derivative falls
    const double q = -0.5 * (B + std::copysign(std::sqrt(discriminant), B));
    for (const double s : {q / A, q != 0.0 ? C / q : q / A})
      if (s > s0 && s < s1 && B + 2.0 * A * s < 0.0) consider(s, cubic(s));
  }
  return peak;
}

inline RungeKuttaNystrom::Weights RungeKuttaNystrom::weights_at(double t) const {
  const double h = time_ - previous_time_;
  const double s = (t - previous_time_) / h, s2 = s * s, s3 = s2 * s;
  Weights w;
  // quintic Hermite: values, first and second derivatives at s = 0 and 1
  w.position = {1.0 - s3 * (10.0 - 15.0 * s + 6.0 * s2),    s - s3 * (6.0 - 8.0 * s + 3.0 * s2),
                0.5 * s2 - s3 * (1.5 - 1.5 * s + 0.5 * s2), s3 * (10.0 - 15.0 * s + 6.0 * s2),
                -s3 * (4.0 - 7.0 * s + 3.0 * s2),           s3 * (0.5 - s + 0.5 * s2)};
  w.rate = {-s2 * (30.0 - 60.0 * s + 30.0 * s2), 1.0 - s2 * (18.0 - 32.0 * s + 15.0 * s2),
            s - s2 * (4.5 - 6.0 * s + 2.5 * s2), s2 * (30.0 - 60.0 * s + 30.0 * s2),
            -s2 * (12.0 - 28.0 * s + 15.0 * s2), s2 * (1.5 - 4.0 * s + 2.5 * s2)};
  w.integral = {1.0 + s2 * (2.0 * s - 3.0), s * (1.0 - s) * (1.0 - s), s2 * (3.0 - 2.0 * s),
                s2 * (s - 1.0)};
  return w;
}

inline double RungeKuttaNystrom::interpolate(const Weights& w, std::size_t i) const {
  const State& y0 = y_[1 - current_];
  const State& y1 = y_[current_];
  const State& f0 = dydt_[1 - current_];
  const State& f1 = dydt_[current_];
  const double h = last_step_;
  if (i < positions_) {  // x, with x' = kappa w, x'' = kappa f
    const std::size_t v = positions_ + i;
    const double hk = h * kappa_;
    return w.position[0] * y0[i] + w.position[1] * hk * y0[v] + w.position[2] * h * hk * f0[v] +
           w.position[3] * y1[i] + w.position[4] * hk * y1[v] + w.position[5] * h * hk * f1[v];
  }
  if (i < 2 * positions_) {  // w = x' / kappa
    // with (x1 - x0) / (h kappa) = w0 + h sum b f, and the weights of w0 and w1 summing to one:
    // w0 plus differences of forces, not the positions' difference (which rounds off to
    // |x| / (h kappa)); the momentum of a group whose forces sum to zero is kept to round-off
    using namespace rkn43;
    const double step_mean = b1 * f0[i] + b2 * stage_[0][i] + b3 * stage_[1][i];
    return y0[i] + w.rate[4] * (y1[i] - y0[i]) +
           h * (w.rate[2] * f0[i] + w.rate[5] * f1[i] - w.rate[0] * step_mean);
  }
  return w.integral[0] * y0[i] + w.integral[1] * h * f0[i] + w.integral[2] * y1[i] +
         w.integral[3] * h * f1[i];
}

}  // namespace mimpact::numerics
