#pragma once

// An independent reference for the tests: the Hertz chain integrated in time with
// Boost.Odeint (Dormand-Prince 5(4), tight tolerances). For e = 1 the LZB impulse dynamics
// is a reparametrization of exactly this model, so both must agree as delta_p -> 0.

#include <Eigen/Dense>
#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <vector>

namespace mimpact::testing {

struct HertzChainOutcome {
  Eigen::VectorXd velocity;   // per body after every contact has opened for good
  Eigen::VectorXd max_force;  // per contact (N)
  double end_time = 0.0;      // s
};

// Bodies of masses `mass` on a line, touching at t = 0, moving with `velocity`; contact i
// (between i and i+1) pushes with K_i delta^1.5 while the overlap delta is positive. With
// `wall_stiffness` > 0 a rigid wall touches the last body. Integrated until no contact
// is loaded and the velocities are non-decreasing to the right (nothing more can happen).
inline HertzChainOutcome integrate_hertz_chain(const Eigen::VectorXd& mass,
                                               const Eigen::VectorXd& velocity,
                                               const Eigen::VectorXd& stiffness,
                                               double tolerance = 1e-12) {
  using State = std::vector<double>;
  const int n = int(mass.size());
  const int contacts = int(stiffness.size());
  auto overlap = [](const State& y, int i) { return y[i] - y[i + 1]; };
  auto rhs = [&](const State& y, State& dydt, double) {
    for (int i = 0; i < n; ++i) {
      dydt[i] = y[n + i];
      dydt[n + i] = 0.0;
    }
    for (int i = 0; i < contacts; ++i) {
      const double delta = overlap(y, i);
      if (delta > 0.0) {
        const double force = stiffness(i) * delta * std::sqrt(delta);
        dydt[n + i] -= force / mass(i);
        dydt[n + i + 1] += force / mass(i + 1);
      }
    }
  };
  State y(2 * n, 0.0);
  for (int i = 0; i < n; ++i) y[n + i] = velocity(i);

  HertzChainOutcome outcome;
  outcome.max_force = Eigen::VectorXd::Zero(contacts);
  auto record = [&](const State& state) {
    for (int i = 0; i < contacts; ++i) {
      const double delta = overlap(state, i);
      if (delta > 0.0)
        outcome.max_force(i) = std::max(outcome.max_force(i), stiffness(i) * std::pow(delta, 1.5));
    }
  };
  auto finished = [&](const State& state) {
    for (int i = 0; i < contacts; ++i)
      if (overlap(state, i) > 0.0 || state[n + i + 1] < state[n + i]) return false;
    return true;
  };

  namespace odeint = boost::numeric::odeint;
  auto stepper =
      odeint::make_dense_output(tolerance, tolerance, odeint::runge_kutta_dopri5<State>());
  const double speed = velocity.cwiseAbs().maxCoeff();
  stepper.initialize(y, 0.0, 1e-9);
  State probe(2 * n);
  // sample the dense output finely so the peak forces are resolved between steps
  while (true) {
    const auto [t0, t1] = stepper.do_step(rhs);
    constexpr int kSamples = 16;
    for (int k = 1; k <= kSamples; ++k) {
      stepper.calc_state(t0 + (t1 - t0) * k / kSamples, probe);
      record(probe);
    }
    if (finished(stepper.current_state()) || t1 > 1e3 / std::max(speed, 1e-12)) break;
  }
  outcome.end_time = stepper.current_time();
  outcome.velocity.resize(n);
  for (int i = 0; i < n; ++i) outcome.velocity(i) = stepper.current_state()[n + i];
  return outcome;
}

}  // namespace mimpact::testing
