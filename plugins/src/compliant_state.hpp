#pragma once

// What the parts of the compliant integrator share: the bodies and contacts as the integration
// sees them, and its state. The parts: compliant_integrator.cpp (the advance: steps, events
// located and handled, the restarts of the integration), compliant_motion.cpp (the moving-body
// set: who is integrated, who flies freely, joins computed in closed form), compliant_ledger.cpp
// (the contact laws' force and energy, the energy ledger), compliant_friction.cpp (Coulomb's law
// on the contacts that rub); the events' classification is a pure function
// (mimpact/numerics/contact_events.hpp).

#include <Eigen/Cholesky>
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <queue>
#include <vector>

#include "mimpact/numerics/contact_events.hpp"
#include "mimpact/numerics/coulomb_phase.hpp"
#include "mimpact/numerics/mindlin_spring.hpp"
#include "mimpact/numerics/ode_options.hpp"
#include "mimpact/plugins/internal/mass_block.hpp"

namespace mimpact::numerics {
class DenseOutput;  // Dormand-Prince 5(4): only compliant_integrator.cpp compiles it
}

namespace mimpact::plugins {
namespace compliant {

using kernel::Index;
using kernel::MatrixXd;
using kernel::VectorXd;

constexpr double kNever = std::numeric_limits<double>::infinity();

// A body of the system: its mass block and how it moves now. Out of the motion it flies
// freely, q(t) = anchor_q + anchor_v (t - anchor_time); in it, its displacement from anchor_q and
// its velocity are part of the integrated state, from slot on.
struct Body : internal::MassBlock {
  bool can_fly = false;  // no force, a constant mass, only linear relations
  bool has_force = false;
  bool in_motion = false;
  Index slot = -1;
  double anchor_time = 0.0;
  int loaded_contacts = 0;  // joined contacts touching it
};

// W_j entry of a linear relation: coordinate `local` of `body`.
struct JacobianEntry {
  Index body = 0, local = 0;
  double value = 0.0;
};

// A contact's Coulomb friction: its tangent rows W_t (constant: linear relations), and either a
// rigid tangential response, its phase (numerics::coulomb::Phase) with time carrying it, or a
// Mindlin spring (numerics::mindlin::Spring) whose stretch is part of the integrated state.
struct Rub {
  int rows = 0;  // 0: frictionless
  double mu = 0.0;
  double spring_ratio = 0.0;  // lambda of its law: k_t / (dF/d delta); 0: rigid
  std::array<std::vector<JacobianEntry>, 2> tangents;
  numerics::coulomb::Phase phase;
  numerics::mindlin::Spring spring;
  std::array<double, 2> stretch{};  // m, the spring's, until the last commit
  Index slot = -1;  // of its first row's tangential impulse in the integrated state, while joined
  Index stretch_slot = -1;          // of its spring's stretch, after every tangential impulse
  std::array<double, 2> impulse{};  // N s along its rows, until the last commit
  // where its slip work was last accounted: the impulses since the last restart (N s), s (m/s)
  std::array<double, 2> accounted_impulse{}, accounted_slip{};
};

struct Contact {
  std::vector<JacobianEntry> entries;  // linear relations: constant
  double anchor_gap = 0.0;             // linear relations: the gap at the bodies' anchors (m)
  bool joined = false;
  // closed at the start or joined since: a gap it has opened since may be frozen
  bool has_closed = false;
  Index slot = -1;       // of its impulse in the integrated state
  double impulse = 0.0;  // N s, until the last commit
  // where its work was last accounted: the impulse since the last restart (N s) and u (m/s)
  double accounted_impulse = 0.0, accounted_rate = 0.0;
  std::uint32_t version = 0;  // invalidates its pending join prediction
  bool predicted = false;
  Rub rub;
};

// A join computed in closed form, between bodies in free flight.
struct PredictedJoin {
  double time;
  Index contact;
  std::uint32_t version;
  bool operator>(const PredictedJoin& other) const { return time > other.time; }
};

// Gaps (m) and rates (m/s) of the watched contacts at one time.
struct GapSamples {
  std::vector<double> gap, rate;
  std::vector<double> friction;  // two per rubbing contact (coulomb::Phase::watched)
};

// The integrator's state (CompliantIntegrator holds one).
struct State {
  using Index = kernel::Index;
  using VectorXd = kernel::VectorXd;

  explicit State(const numerics::OdeOptions& options);
  ~State();

  std::unique_ptr<numerics::DenseOutput> dense;
  std::vector<double> y, probe;  // the integrated state and a workspace
  bool linear = true;
  double join_overlap = 0.0, leave_overlap = 0.0;  // m
  std::vector<compliant::Body> bodies;
  std::vector<compliant::Contact> contacts;
  VectorXd anchor_q, anchor_v;  // global coordinates
  std::vector<Index> body_of_coordinate, local_of_coordinate;
  // The motion: its bodies, its joined contacts, the contacts watched for events, and the joins
  // predicted in closed form between bodies in free flight.
  struct Motion {
    std::vector<Index> moving, joined, watched;
    Index coordinates = 0, most_moving = 0;  // of the moving bodies; the most bodies at once
    std::vector<std::uint32_t> watch_stamp;
    std::uint32_t stamp = 0;
    std::priority_queue<compliant::PredictedJoin, std::vector<compliant::PredictedJoin>,
                        std::greater<>>
        predictions;
    Index pending_predictions = 0;
    // the contact of the event handled last: its crossing, seen again at the start of the next
    // segment through round-off of the restarted state, is not an event
    Index last_event = -1;
  };
  // The right-hand side's and the event search's workspace.
  struct Scratch {
    VectorXd generalized;
    VectorXd q_all, v_all;  // nonlinear relations: every coordinate
    compliant::GapSamples before, after;
    std::vector<double> event_gap, event_rate;
    std::vector<double> gap_now;  // m, of the joined contacts at the end of the last segment
  };
  // The forces' work: the moving coordinates' velocities and the time where it was last
  // accounted.
  struct Ledger {
    std::vector<double> accounted_velocity;
    double accounted_time = 0.0;
  };
  // The joined contacts that rub, their tangential impulses in y from `first_slot` on (after the
  // normal impulses) and then their springs' stretches, and the workspace of their forces: per slot
  // s (m/s) and the tangential force (N); the sticking slots and their block of H_tt = W_t^T M^-1
  // W_t, factorized.
  struct Friction {
    bool on = false;              // some contact has friction
    double slip_tolerance = 0.0;  // m/s
    double segment_start = 0.0;   // s, of the restart
    std::vector<Index> rubbing;
    Index first_slot = 0, slots = 0;
    std::vector<double> slip, force;
    std::vector<std::pair<Index, int>> sticking;  // (contact, row)
    Eigen::LDLT<MatrixXd> stick_factor;
    VectorXd stick_force, stick_generalized;
    std::vector<double> dydt;    // the right-hand side where the watched values are read
    std::vector<double> values;  // the watched values at one time, while narrowing
  };
  Motion motion;
  Scratch scratch;
  Ledger ledger;
  Friction friction;

  compliant::Body& body(Index k) { return bodies[std::size_t(k)]; }
  compliant::Contact& contact(Index j) { return contacts[std::size_t(j)]; }

  // displacement from the anchor and velocity of coordinate `local` of body k at time t, with
  // the integrated state y
  double displacement(const compliant::Body& b, Index local, double t, const double* state) const {
    return b.in_motion ? state[b.slot + local] : anchor_v(b.offset + local) * (t - b.anchor_time);
  }
  double velocity(const compliant::Body& b, Index local, const double* state) const {
    return b.in_motion ? state[motion.coordinates + b.slot + local] : anchor_v(b.offset + local);
  }
};

// An event of a contact: when it joins, leaves, turns or stops separating.
struct Event {
  kernel::Index contact = -1;
  numerics::ContactEvent kind = numerics::ContactEvent::none;
  double time = 0.0;
  // a switch of the contact's Coulomb phase instead (kind none): its first watched value
  // crossed (a slip stopped or a stick ended), or its second (a slip from rest grew free)
  int coulomb = -1;
};

// Gap and rate of contact j along the integrated state y at time t.
template <class StateT>
void linear_gap(const StateT& s, const Contact& c, double t, const double* y, double& gap,
                double& rate) {
  gap = c.anchor_gap;
  rate = 0.0;
  for (const JacobianEntry& entry : c.entries) {
    const Body& b = s.bodies[std::size_t(entry.body)];
    gap += entry.value * s.displacement(b, entry.local, t, y);
    rate += entry.value * s.velocity(b, entry.local, y);
  }
}

}  // namespace compliant
}  // namespace mimpact::plugins
