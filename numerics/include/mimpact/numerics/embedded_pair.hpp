#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace mimpact::numerics {

// An embedded Runge-Kutta pair with error control and dense output on a flat state: what it
// keeps between steps (the state and its derivative at both ends of the last step) and its
// step loop, shared by DenseOutput (Dormand-Prince 5(4)) and RungeKuttaNystrom (RKN4(3)4FM).
// Derived, a friend, gives its pair and its step-size controller:
//   double attempt(Rhs& rhs, double h)  a step of h from state() into the other buffer, with
//                                       its derivative there; returns the largest error ratio
//   bool admit(double& h)               bounds the step about to be tried (false: try again)
//   double after_rejection(double h, double error), after_acceptance(double h, double error)
//                                       the next step
//   Weights weights_at(double t), double interpolate(const Weights&, std::size_t i)
//                                       its dense output over the last step
template <class Derived>
class EmbeddedPair {
 public:
  using State = std::vector<double>;

  // Marks the motion as changed: the next step must restart it.
  void invalidate() { started_ = false; }
  // The right-hand side changed at the current state, which stands (a contact's law turned
  // there): the next step forms its derivative anew rather than taking the last step's.
  void refresh_derivative() { derivative_known_ = false; }
  bool started() const { return started_; }

  // One step of the motion from time(), rhs(y, dydt, t) its right-hand side: [previous time,
  // time()] becomes known.
  template <class Rhs>
  void step(Rhs&& rhs);

  double time() const { return time_; }
  const State& state() const { return y_[current_]; }
  // The state at a time of the last step.
  void state_at(double t, State& y) const {
    const Derived& self = static_cast<const Derived&>(*this);
    const auto w = self.weights_at(t);
    y.resize(y_[current_].size());
    for (std::size_t i = 0; i < y.size(); ++i) y[i] = self.interpolate(w, i);
  }
  // The state at the start of the last step.
  const State& start_state() const { return y_[1 - current_]; }
  // The state at the end of the last step, to amend what the pair's stages could not form (a
  // switch within the step): the next step forms its derivative there anew. The dense output
  // over the last step stays the pair's own.
  State& amend_end() {
    derivative_known_ = false;
    return y_[current_];
  }
  // The length of the last step (s), 0 before the first.
  double last_step() const { return last_step_; }
  // The step the controller would try next (s).
  double next_step() const { return next_step_; }
  // Steps taken since construction.
  std::int64_t steps() const { return steps_; }

 protected:
  // `name` says which pair failed, in the error a step that cannot meet its tolerance throws.
  EmbeddedPair(const char* name, double absolute_tolerance, double relative_tolerance,
               double max_step)
      : name_(name),
        absolute_(absolute_tolerance),
        relative_(relative_tolerance),
        max_step_(max_step) {}

  // Starts again from (t, y) with a first step of `first_step`.
  void start(const State& y, double t, double first_step) {
    current_ = 0;
    y_[0] = y;
    y_[1].resize(y.size());
    for (State& k : dydt_) k.resize(y.size());
    time_ = t;
    next_step_ = first_step;
    derivative_known_ = false;
    started_ = true;
  }

  const char* name_;
  double absolute_, relative_, max_step_;  // error control: absolute + relative (|y| + h |y'|)
  std::array<State, 2> y_, dydt_;          // the state and its derivative at the step's two ends
  std::size_t current_ = 0;                // of y_ and dydt_: the end of the last step
  double time_ = 0.0, previous_time_ = 0.0, next_step_ = 0.0, last_step_ = 0.0;
  bool derivative_known_ = false;
  bool started_ = false;
  std::int64_t steps_ = 0;

 private:
  // failed attempts at one step before the step size is deemed unable to reach the tolerance
  static constexpr int kMostFailures = 500;
};

template <class Derived>
template <class Rhs>
void EmbeddedPair<Derived>::step(Rhs&& rhs) {
  Derived& self = static_cast<Derived&>(*this);
  if (!derivative_known_) {
    rhs(y_[current_], dydt_[current_], time_);
    derivative_known_ = true;
  }
  previous_time_ = time_;
  for (int failures = 0;; ++failures) {
    if (failures >= kMostFailures)
      throw std::runtime_error(std::string(name_) + ": " + std::to_string(kMostFailures) +
                               " failed attempts at one step: the tolerance cannot be met");
    double h = next_step_;
    if (!self.admit(h)) continue;
    const double error = self.attempt(rhs, h);
    if (error > 1.0) {
      next_step_ = self.after_rejection(h, error);
      continue;
    }
    time_ += h;
    next_step_ = self.after_acceptance(h, error);
    break;
  }
  current_ = 1 - current_;
  last_step_ = time_ - previous_time_;
  ++steps_;
}

}  // namespace mimpact::numerics
