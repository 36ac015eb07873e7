#pragma once

#include <boost/numeric/odeint.hpp>
#include <cstdint>
#include <vector>

#include "mimpact/numerics/ode_options.hpp"

namespace mimpact::numerics::internal {

// Dormand-Prince 5(4) with error control and dense output (Boost.Odeint) on a flat state:
// after each step the state is known at every time of the step, for the event search. The
// state may change size at a restart: an integrator that carries only the bodies or contacts
// taking part restarts with a new set after an event.
class DenseOutput {
 public:
  using State = std::vector<double>;

  explicit DenseOutput(const OdeOptions& options)
      : DenseOutput(options.absolute_tolerance, options.relative_tolerance, options.max_step) {}

  // Error control to absolute + relative * |y| per component; max_step 0: no limit.
  DenseOutput(double absolute_tolerance, double relative_tolerance, double max_step = 0.0)
      : dense_(max_step > 0.0 ? boost::numeric::odeint::make_dense_output(
                                    absolute_tolerance, relative_tolerance, max_step, Stepper())
                              : boost::numeric::odeint::make_dense_output(
                                    absolute_tolerance, relative_tolerance, Stepper())) {}

  // Starts again from (t, y), with a first step of `first_step`.
  void restart(const State& y, double t, double first_step) {
    dense_.initialize(y, t, first_step);
    started_ = true;
  }
  // Marks the motion as changed: the next step must restart it.
  void invalidate() { started_ = false; }
  bool started() const { return started_; }

  // One step of y' = rhs(y, dydt, t) from time(): [previous time, time()] becomes known.
  template <class Rhs>
  void step(Rhs&& rhs) {
    const auto [from, to] = dense_.do_step(rhs);
    last_step_ = to - from;
    ++steps_;
  }

  double time() const { return dense_.current_time(); }
  const State& state() const { return dense_.current_state(); }
  // The state at a time of the last step.
  void state_at(double t, State& y) const { dense_.calc_state(t, y); }
  // The length of the last step (s), 0 before the first.
  double last_step() const { return last_step_; }
  // Steps taken since construction.
  std::int64_t steps() const { return steps_; }

 private:
  using Stepper = boost::numeric::odeint::runge_kutta_dopri5<
      State, double, State, double, boost::numeric::odeint::range_algebra,
      boost::numeric::odeint::default_operations, boost::numeric::odeint::always_resizer>;
  using Dense = boost::numeric::odeint::result_of::make_dense_output<Stepper>::type;

  Dense dense_;
  bool started_ = false;
  double last_step_ = 0.0;
  std::int64_t steps_ = 0;
};

}  // namespace mimpact::numerics::internal
