#pragma once

// Coulomb's law on the persistent contacts of the event-driven scheme's smooth motion
// (docs/friction.md, section 5): a held contact with friction mu > 0 and tangent rows slips with
// the force -mu lambda d (d the slip's direction, numerics::coulomb::Phase) or sticks with the
// force that keeps its slip's acceleration 0, within its cone. With S the sticking rows, L the
// slipping ones and P the held contacts, the normal forces lambda and the sticking forces f_S
// solve together
//   W_P^T a + c_P = 0,   W_S^T a + c_S = 0,   a = M^-1 (F + W_P lambda + W_S f_S + W_L D lambda),
// c the rows' (dW/dt)^T v and D lambda the slipping rows' forces (-mu d lambda per contact): a
// square system, not symmetric where contacts slip, solved by LU. Its switches (a slip stops,
// a stick's force reaches the cone) are events the integrator locates, as the impacts' are.
// Which contacts stay held is the frictionless acceleration-level problem's answer, less those
// whose normal force friction turns negative.

#include <Eigen/Dense>
#include <array>
#include <span>
#include <vector>

#include "mimpact/kernel/non_smooth_dynamical_system.hpp"
#include "mimpact/numerics/coulomb_phase.hpp"

namespace mimpact::plugins {

class ContactDynamics;

class SmoothFriction {
 public:
  // mu of every interaction with tangent rows and an LzbLaw; slip_tolerance (m/s): a slower
  // slip starts as a stick.
  void initialize(const kernel::NonSmoothDynamicalSystem& system, double slip_tolerance);
  // The persistent contacts at (t, q, v) that rub get their phases (slip where their slip is
  // above the tolerance, else stick while within the cone: coulomb::settle_sticks). Returns the
  // persistent contacts whose normal force stays >= 0 with friction.
  std::vector<kernel::Index> hold(std::span<const kernel::Index> persistent, double t,
                                  const kernel::VectorXd& q, const kernel::VectorXd& v,
                                  ContactDynamics& dynamics);
  bool rubbing() const { return !rubs_.empty(); }
  // The acceleration and the held contacts' normal forces at (q, v), `dynamics` evaluated there
  // on the persistent set.
  void accelerate(ContactDynamics& dynamics, const kernel::VectorXd& q, const kernel::VectorXd& v,
                  kernel::VectorXd& acceleration, kernel::VectorXd& normal);
  // Two values per rubbing contact (coulomb::Phase::watched), > 0 before a switch, from the last
  // accelerate().
  void watched(kernel::VectorXd& values) const;
  // Past the switch of watched value `which` (0 or 1) of rubbing contact `rub`.
  void pass(std::size_t rub, int which);
  // The phases settled at (t, q, v) after switches (coulomb::settle_sticks).
  void settle(double t, const kernel::VectorXd& q, const kernel::VectorXd& v,
              ContactDynamics& dynamics);

 private:
  struct Rub {
    kernel::Index contact = 0;  // interaction
    std::size_t held = 0;       // its place among the persistent contacts
    int rows = 0;
    kernel::Index first_row = 0;  // of its rows among the rubbing contacts'
    numerics::coulomb::Phase phase;
    double limit = 0.0;                     // mu lambda (N), at the last accelerate()
    std::array<double, 2> slip{}, force{};  // m/s, N
  };

  const kernel::NonSmoothDynamicalSystem* system_ = nullptr;
  std::vector<double> mu_;
  double slip_tolerance_ = 0.0;
  std::vector<kernel::Index> persistent_;
  std::vector<Rub> rubs_;
  kernel::VectorXd rates_, acceleration_, normal_;
  Eigen::MatrixXd mobility_, tangent_mobility_;  // M^-1 W_P, M^-1 W_t
};

}  // namespace mimpact::plugins
