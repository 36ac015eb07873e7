#pragma once

// What the event-driven integrator's parts share (event_driven_integrator.cpp: the smooth
// motion and its events; event_driven_settle.cpp: algorithm 6 before each motion).

#include <optional>

#include "contact_dynamics.hpp"
#include "mimpact/numerics/dense_output.hpp"
#include "smooth_friction.hpp"

namespace mimpact::plugins {

using kernel::VectorXd;

// What the event search watches at one time: every contact's gap (m) and normal velocity
// (m/s), the force holding each persistent contact (N), and the Coulomb phases' watched values
// of those that rub (SmoothFriction::watched).
struct EventDrivenWatch {
  VectorXd gaps, rates, forces, friction;
};

// The smooth motion: the contact dynamics with the persistent contacts held, its integration
// (Dormand-Prince 5(4) with dense output, on y = (q, v); only once some force acts), and the
// event search's workspace.
struct EventDrivenMotion {
  ContactDynamics dynamics;
  SmoothFriction friction;
  double phases_since = 0.0;  // s: where the rubbing contacts' phases were last chosen
  std::optional<numerics::DenseOutput> dense;
  numerics::DenseOutput::State y, probe;
  VectorXd q, v, a, normal;  // right-hand side workspace
  VectorXd q_probe, v_probe;
  EventDrivenWatch before, after, probed;
  VectorXd levels;  // the gap at which each contact counts as closing, in a search
};

}  // namespace mimpact::plugins
