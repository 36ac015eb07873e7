#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "mimpact/numerics/embedded_pair.hpp"
#include "mimpact/numerics/ode_options.hpp"

namespace mimpact::numerics {

// Dormand-Prince 5(4) with error control and dense output on a flat state (Dormand & Prince,
// J. Comput. Appl. Math. 6, 1980; the continuous extension of Hairer, Norsett & Wanner, Solving
// Ordinary Differential Equations I, section II.6): after each step the state is known at every
// time of the step, for the event search. The state may change size at a restart: an integrator
// that carries only the bodies or contacts taking part restarts with a new set after an event.
//
// The step, its error control and its interpolation are Boost.Odeint's runge_kutta_dopri5 in
// its dense-output controller, operation for operation (a run gives the same numbers), with
// what the moving geometry needs and Odeint cannot give: one component at a time out of the
// dense output (a group's event search reads the few bodies it watches, not its whole state),
// stages formed only where the right-hand side reads them (a contact's impulse, the integral
// of its force, is read by no derivative), and no reallocation at every step.
//
// A right-hand side with adjust_error(State& error) is handed each attempt's error estimate
// (per component, before the tolerance divides it) to take out what it amends itself after the
// step (a switch within it, which its stages could not integrate).
class DenseOutput : public EmbeddedPair<DenseOutput> {
 public:
  explicit DenseOutput(const OdeOptions& options)
      : DenseOutput(options.absolute_tolerance, options.relative_tolerance, options.max_step) {}

  // Error control to absolute + relative (|y| + h |y'|) per component, the largest of the
  // ratios below 1; max_step 0: no limit.
  DenseOutput(double absolute_tolerance, double relative_tolerance, double max_step = 0.0)
      : EmbeddedPair("Dormand-Prince", absolute_tolerance, relative_tolerance, max_step) {}

  // Starts again from (t, y), with a first step of `first_step`. The right-hand side reads the
  // first `read` components only (the others' derivatives depend on those alone): the stages
  // form those, and every component is stepped, interpolated and held to the tolerance alike.
  void restart(const State& y, double t, double first_step, std::size_t read = kAll) {
    start(y, t, first_step);
    for (State& k : stage_) k.resize(y.size());
    probe_.resize(y.size());
    read_ = std::min(read, y.size());
  }

  // The weights of the continuous extension at a time of the last step, for component_at.
  struct Weights {
    std::array<double, 6> of{};  // h b_i(theta) of k1, k3, k4, k5, k6, k7 (b_2(theta) = 0)
  };
  Weights weights_at(double t) const;
  // Component i of the state at the weights' time: the same number as state_at gives.
  double component_at(const Weights& w, std::size_t i) const { return interpolate(w, i); }

 private:
  friend class EmbeddedPair<DenseOutput>;
  static constexpr std::size_t kAll = std::size_t(-1);

  // the stages k2..k6 and the error estimate of a step of h from the current state into the
  // other buffer, with its derivative there (k7); returns the largest error ratio
  template <class Rhs>
  double attempt(Rhs& rhs, double h);
  // Odeint's step adjuster: a rejected step shrinks by 0.9 err^(-1/3), at most fivefold; an
  // accepted one with err < 1/2 grows by 0.9 err^(-1/5), at most fivefold; max_step bounds
  // both (a step above it counts as an attempt failed).
  bool admit(double& h) {
    if (max_step_ > 0.0 && !(h <= max_step_)) {
      next_step_ = max_step_;
      return false;
    }
    return true;
  }
  double after_rejection(double h, double error) const {
    return bounded(h * std::max(0.9 * std::pow(error, -1.0 / 3.0), 1.0 / 5.0));
  }
  double after_acceptance(double h, double error) const {
    if (!(error < 0.5)) return h;
    return bounded(h * (0.9 * std::pow(std::max(std::pow(5.0, -5.0), error), -1.0 / 5.0)));
  }
  double bounded(double h) const { return max_step_ > 0.0 ? std::min(h, max_step_) : h; }
  double interpolate(const Weights& w, std::size_t i) const {
    const State& y0 = y_[1 - current_];
    const State& k1 = dydt_[1 - current_];
    const State& k7 = dydt_[current_];
    return 1.0 * y0[i] + w.of[0] * k1[i] + w.of[1] * stage_[1][i] + w.of[2] * stage_[2][i] +
           w.of[3] * stage_[3][i] + w.of[4] * stage_[4][i] + w.of[5] * k7[i];
  }

  std::array<State, 5> stage_;  // k2..k6
  State probe_;                 // the state at a stage
  std::size_t read_ = 0;        // components the right-hand side reads
  State error_;                 // the error estimate, for a right-hand side that adjusts it
};

// The Butcher tableau of Dormand-Prince 5(4): nodes c, stage weights a, the fifth-order
// weights b and their difference e to the embedded fourth-order ones.
namespace dopri5 {
constexpr double c2 = 1.0 / 5.0, c3 = 3.0 / 10.0, c4 = 4.0 / 5.0, c5 = 8.0 / 9.0;
constexpr double a21 = 1.0 / 5.0;
constexpr double a31 = 3.0 / 40.0, a32 = 9.0 / 40.0;
constexpr double a41 = 44.0 / 45.0, a42 = -56.0 / 15.0, a43 = 32.0 / 9.0;
constexpr double a51 = 19372.0 / 6561.0, a52 = -25360.0 / 2187.0, a53 = 64448.0 / 6561.0,
                 a54 = -212.0 / 729.0;
constexpr double a61 = 9017.0 / 3168.0, a62 = -355.0 / 33.0, a63 = 46732.0 / 5247.0,
                 a64 = 49.0 / 176.0, a65 = -5103.0 / 18656.0;
constexpr double b1 = 35.0 / 384.0, b3 = 500.0 / 1113.0, b4 = 125.0 / 192.0, b5 = -2187.0 / 6784.0,
                 b6 = 11.0 / 84.0;
constexpr double e1 = b1 - 5179.0 / 57600.0, e3 = b3 - 7571.0 / 16695.0, e4 = b4 - 393.0 / 640.0,
                 e5 = b5 - -92097.0 / 339200.0, e6 = b6 - 187.0 / 2100.0, e7 = -1.0 / 40.0;
}  // namespace dopri5

template <class Rhs>
double DenseOutput::attempt(Rhs& rhs, double h) {
  using namespace dopri5;
  const State& y = y_[current_];
  const State& k1 = dydt_[current_];
  State& out = y_[1 - current_];
  State& k7 = dydt_[1 - current_];
  auto& [k2, k3, k4, k5, k6] = stage_;
  const std::size_t n = y.size(), read = read_;
  const double t = time_;
  // the products h a_ij first, then the sums in the tableau's order (Odeint's scale_sum)
  for (std::size_t i = 0; i < read; ++i) probe_[i] = 1.0 * y[i] + h * a21 * k1[i];
  rhs(probe_, k2, t + h * c2);
  for (std::size_t i = 0; i < read; ++i) probe_[i] = 1.0 * y[i] + h * a31 * k1[i] + h * a32 * k2[i];
  rhs(probe_, k3, t + h * c3);
  for (std::size_t i = 0; i < read; ++i)
    probe_[i] = 1.0 * y[i] + h * a41 * k1[i] + h * a42 * k2[i] + h * a43 * k3[i];
  rhs(probe_, k4, t + h * c4);
  for (std::size_t i = 0; i < read; ++i)
    probe_[i] = 1.0 * y[i] + h * a51 * k1[i] + h * a52 * k2[i] + h * a53 * k3[i] + h * a54 * k4[i];
  rhs(probe_, k5, t + h * c5);
  for (std::size_t i = 0; i < read; ++i)
    probe_[i] = 1.0 * y[i] + h * a61 * k1[i] + h * a62 * k2[i] + h * a63 * k3[i] + h * a64 * k4[i] +
                h * a65 * k5[i];
  rhs(probe_, k6, t + h);
  for (std::size_t i = 0; i < n; ++i)
    out[i] = 1.0 * y[i] + h * b1 * k1[i] + h * b3 * k3[i] + h * b4 * k4[i] + h * b5 * k5[i] +
             h * b6 * k6[i];
  rhs(out, k7, t + h);
  auto error_of = [&](std::size_t i) {
    return h * e1 * k1[i] + h * e3 * k3[i] + h * e4 * k4[i] + h * e5 * k5[i] + h * e6 * k6[i] +
           h * e7 * k7[i];
  };
  constexpr bool kAdjusts = requires(Rhs & r, State & e) { r.adjust_error(e); };
  if constexpr (kAdjusts) {
    error_.resize(n);
    for (std::size_t i = 0; i < n; ++i) error_[i] = error_of(i);
    rhs.adjust_error(error_);
  }
  double largest = 0.0;
  const double h_abs = 1.0 * std::abs(h);
  for (std::size_t i = 0; i < n; ++i) {
    const double error = kAdjusts ? error_[i] : error_of(i);
    largest = std::max(
        largest, std::abs(error) /
                     (absolute_ + relative_ * (1.0 * std::abs(y[i]) + h_abs * std::abs(k1[i]))));
  }
  return largest;
}

inline DenseOutput::Weights DenseOutput::weights_at(double t) const {
  using namespace dopri5;
  const double h = time_ - previous_time_;
  const double theta = (t - previous_time_) / h;
  const double X1 = 5.0 * (2558722523.0 - 31403016.0 * theta) / 11282082432.0;
  const double X3 = 100.0 * (882725551.0 - 15701508.0 * theta) / 32700410799.0;
  const double X4 = 25.0 * (443332067.0 - 31403016.0 * theta) / 1880347072.0;
  const double X5 = 32805.0 * (23143187.0 - 3489224.0 * theta) / 199316789632.0;
  const double X6 = 55.0 * (29972135.0 - 7076736.0 * theta) / 822651844.0;
  const double X7 = 10.0 * (7414447.0 - 829305.0 * theta) / 29380423.0;
  const double theta_m_1 = theta - 1.0;
  const double theta_sq = theta * theta;
  const double A = theta_sq * (3.0 - 2.0 * theta);
  const double B = theta_sq * theta_m_1;
  const double C = theta_sq * theta_m_1 * theta_m_1;
  const double D = theta * theta_m_1 * theta_m_1;
  return {{h * (A * b1 - C * X1 + D), h * (A * b3 + C * X3), h * (A * b4 - C * X4),
           h * (A * b5 + C * X5), h * (A * b6 - C * X6), h * (B + C * X7)}};
}

}  // namespace mimpact::numerics
