#pragma once

// The state of one adaptive LZB impact that its integration (adaptive_lzb::Impact) and its
// within-steps strategy (adaptive_lzb::WithinSteps) share: the contacts' law constants, their
// states at the current segment's start and the segment itself (docs/design/adaptive_lzb.md).

#include <Eigen/Sparse>
#include <algorithm>
#include <cstddef>
#include <optional>
#include <vector>

#include "mimpact/numerics/contact_law.hpp"
#include "mimpact/numerics/dense_output.hpp"
#include "mimpact/numerics/root_bracketing.hpp"

namespace mimpact::numerics::adaptive_lzb {

// Where a contact is in its cycle (docs/model.md, section 10).
enum class Phase : unsigned char { open, compression, expansion };

// The switches of the right-hand side, each located as an event.
enum EventKind : int {
  join = 0,         // an open contact starts approaching: it enters compression at delta = 0
  compression_end,  // u_j reaches 0 from below: delta_j is at its largest, expansion begins
  reload,           // u_j of an expanding contact turns negative: compression again
  release,          // delta_j reaches its release level: the contact leaves the impact
  // with friction (lzb_adaptive_friction.hpp), of a contact's tangential rows:
  slip_stop,   // its slip stops (plane: s crosses 0; space: |s| falls to tolerance * V)
  stick_end,   // the force that keeps it stuck reaches mu F: it slips
  slip_armed,  // a slip started from rest has grown to 2 tolerance * V: its direction is free
};

// The watched quantities at one time: the members' velocities and the active ones' delta;
// with friction, two per frictional member (Friction::watch).
struct Watched {
  std::vector<double> velocity, delta, friction;
};

// Per contact: the law's constants and scales, fixed for the impact.
struct ContactConstants {
  std::vector<double> stiffness, exponent, expansion_rate, release_factor;
  std::vector<double> delta_scale, impulse_scale, energy_tolerance;
  std::vector<double> self_mobility;     // H_jj (1/kg)
  std::vector<bool> gives_nothing_back;  // e = 0

  void reset(std::size_t m) {
    for (auto* values : {&stiffness, &exponent, &expansion_rate, &release_factor, &delta_scale,
                         &impulse_scale, &energy_tolerance, &self_mobility})
      values->assign(m, 0.0);
    gives_nothing_back.assign(m, false);
  }
  double force(Eigen::Index j, double delta) const {  // N
    return stiffness[j] * power_law(delta, exponent[j]);
  }
  double energy(Eigen::Index j, double delta) const {  // J
    return force(j, delta) * delta / (1.0 + exponent[j]);
  }
};

// Per contact: the state at the start of the current segment.
struct ContactStates {
  std::vector<Phase> phase;
  std::vector<double> delta, impulse, velocity, release_level, max_force, time_of_max;
  std::vector<double> work;    // J, the integral of -u_j dP_j so far
  std::vector<int> member_of;  // the contact's place in the segment's members, -1 if none

  // open, unloaded, at u- (one entry per contact)
  void reset(const Eigen::VectorXd& u_minus) {
    const auto m = std::size_t(u_minus.size());
    phase.assign(m, Phase::open);
    for (auto* values : {&delta, &impulse, &release_level, &max_force, &time_of_max, &work})
      values->assign(m, 0.0);
    member_of.assign(m, -1);
    velocity.assign(u_minus.data(), u_minus.data() + m);
  }
};

// The current segment (between two switches). Contacts are its members when they hold energy
// (active: their delta_j and the increment of P_j since the segment began are the ODE's state,
// scaled to order one) or when an active one pushes them (watched: open, their velocity
// followed to catch them joining). The other contacts do not change and cost nothing.
struct Segment {
  using State = DenseOutput::State;
  std::vector<Eigen::Index> members;  // the active contacts first, then the watched ones
  std::size_t active = 0;
  // per active member: d delta_j/dt = -rate u_j over the segment (1, or 1/e^2 expanding)
  std::vector<double> rate;
  State y, y_at;
  std::vector<double> rhs_velocity, velocity_at;
  // per active member: its impulse increment and velocity where the work was last accounted
  std::vector<double> accounted_impulse, accounted_velocity;
  Watched before, after;
  std::vector<Eigen::Index> previous_members;  // begin_segment's buffer
};

// What the integration and its strategies read and write: H, the contacts and the segment.
struct ImpactState {
  using State = DenseOutput::State;
  const Eigen::SparseMatrix<double>* H = nullptr;
  ContactConstants law;
  ContactStates contact;
  Segment segment;
  double velocity_tolerance = 0.0;  // tolerance * V (m/s)
  double local_tolerance = 0.0;     // a step's error share, in the state's scaled units

  // contact j holds energy or approaches faster than tolerance * V (at the last segment's end)
  bool takes_part(Eigen::Index j) const {
    return contact.delta[j] > 0.0 || contact.velocity[j] < -velocity_tolerance;
  }
  // m: active member a's delta_j at the state y
  double delta_of(std::size_t member, const State& y) const {
    return std::max(y[member], 0.0) * law.delta_scale[segment.members[member]];
  }
  // u_j of one member from its column of H alone (H is symmetric: column j holds row j, the
  // contacts whose impulses move u_j); `impulse(a)` gives active member a's scaled P increment
  template <class Impulse>
  double column_velocity(std::size_t member, Impulse&& impulse) const {
    const Eigen::Index j = segment.members[member];
    double velocity = contact.velocity[j];
    const int* start = H->outerIndexPtr();
    const int* row = H->innerIndexPtr();
    const double* value = H->valuePtr();
    for (int k = start[j]; k < start[j + 1]; ++k) {
      const int other = contact.member_of[row[k]];
      if (other >= 0 && std::size_t(other) < segment.active)
        velocity += value[k] * impulse(std::size_t(other)) * law.impulse_scale[row[k]];
    }
    return velocity;
  }
};

}  // namespace mimpact::numerics::adaptive_lzb
