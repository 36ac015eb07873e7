#include <algorithm>

#include "event_driven_motion.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/plugins/event_driven_integrator.hpp"

// The event-driven scheme's settling before each smooth motion (algorithm 6 of Nguyen &
// Brogliato 2011): penetrations undone, contacts brought to rest, and those held closed chosen,
// with their Coulomb phases where they rub.
namespace mimpact::plugins {

// Algorithm 6 of Nguyen & Brogliato (2011), before the next smooth motion: penetrations are
// undone, contacts come to rest, and the contact force problem decides which stay closed.
// A contact sent into a real approach by any of this makes an impact now instead.
void EventDrivenIntegrator::settle(kernel::StepReport& report) {
  restore_penetrations();
  const std::vector<Index> resting = bring_to_rest();
  if (impact_pending_) {
    system_->scatter_state(q_, v_);
    return;
  }
  hold_resting(resting, report);
}

// Events are placed just after a crossing, so closed contacts penetrate a little, and a
// contact that closes again while already closed sinks deeper each time: the least
// mass-weighted shift of positions, dq = M^-1 W lambda with H lambda = -g over the
// penetrating contacts, brings them back to g = 0. Shifting one may press a neighbour in:
// the set grows until no closed contact penetrates.
void EventDrivenIntegrator::restore_penetrations() {
  ContactDynamics& dynamics = motion_->dynamics;
  std::vector<Index> penetrating;
  for (std::size_t round = 0; round <= closed_.size(); ++round) {
    bool added = false;
    for (Index j : closed_)
      if (system_->gap(j, q_) < 0.0 &&
          std::find(penetrating.begin(), penetrating.end(), j) == penetrating.end()) {
        penetrating.push_back(j);
        added = true;
      }
    if (!added) break;
    VectorXd g(Index(penetrating.size()));
    for (std::size_t k = 0; k < penetrating.size(); ++k)
      g(Index(k)) = system_->gap(penetrating[k], q_);
    dynamics.evaluate(time_, q_, v_, penetrating);
    const VectorXd shift = dynamics.solve(-g);
    dynamics.add_mobility_times(shift, q_);
  }
}

// Contacts come to rest when |u| is within what the last impact resolves or their next
// flight would be too short; the least-energy velocity change then sets their u to 0. That
// change moves the other closed contacts too, so the classification repeats until nothing
// changes. Sets impact_pending_ when a closed contact approaches for real.
std::vector<Index> EventDrivenIntegrator::bring_to_rest() {
  ContactDynamics& dynamics = motion_->dynamics;
  std::vector<Index> resting;
  std::vector<char> rests(std::size_t(system_->interaction_count()), 0);
  for (std::size_t round = 0; round <= closed_.size(); ++round) {
    dynamics.evaluate(time_, q_, v_, {});
    const VectorXd& free_acceleration = dynamics.free_acceleration();
    bool added = false;
    for (Index j : closed_) {
      if (rests[std::size_t(j)]) continue;
      const double u = system_->velocity(j, q_, v_);
      // an impact may leave a contact approaching as slowly as its velocity resolution:
      // that is rest, not a new impact; a separation, however slow, is real unless its
      // flight would be shorter than rest_flight_time
      const double resolution = std::max(options_.velocity_tolerance, velocity_resolution_(j));
      if (u < -resolution) {
        impact_pending_ = true;
        return resting;
      }
      double b = system_->jacobian_rate(j, q_, v_);
      system_->for_each_jacobian_entry(j, q_,
                                       [&](Index i, double w) { b += w * free_acceleration(i); });
      const double rest_speed = b < 0.0 ? 0.5 * -b * options_.rest_flight_time : 0.0;
      if (u <= std::max(options_.velocity_tolerance, rest_speed)) {
        resting.push_back(j);
        rests[std::size_t(j)] = 1;
        added = true;
      }
    }
    if (!added) break;
    VectorXd u(Index(resting.size()));
    for (std::size_t k = 0; k < resting.size(); ++k)
      u(Index(k)) = system_->velocity(resting[k], q_, v_);
    if (u.cwiseAbs().maxCoeff() > 0.0) {
      dynamics.evaluate(time_, q_, v_, resting);
      const VectorXd impulse = dynamics.solve(-u);
      dynamics.add_mobility_times(impulse, v_);
    }
  }
  return resting;
}

// Which resting contacts stay closed: the acceleration-level problem. They are held in the
// smooth motion that follows, which is q + v t when no force acts and every held relation is
// linear.
void EventDrivenIntegrator::hold_resting(const std::vector<Index>& resting,
                                         kernel::StepReport& report) {
  std::vector<Index> persistent;
  if (!resting.empty()) {
    kernel::ContactForces forces = forces_->solve(*system_, resting, time_, q_, v_);
    if (!forces.solved)
      throw Error("contact forces at t = " + to_text(time_) + " s: " + forces.message);
    // a contact pulled away more slowly than this would separate less than the velocity
    // tolerance over a rest flight time: it stays
    const double acceleration_tolerance =
        options_.rest_flight_time > 0.0
            ? 2.0 * options_.velocity_tolerance / options_.rest_flight_time
            : 0.0;
    for (std::size_t k = 0; k < resting.size(); ++k)
      if (forces.force(Index(k)) > 0.0 || forces.acceleration(Index(k)) <= acceleration_tolerance)
        persistent.push_back(resting[k]);
    report.contact_forces = std::move(forces);
  }
  if (!persistent.empty())
    persistent = motion_->friction.hold(persistent, time_, q_, v_, motion_->dynamics);
  motion_->phases_since = time_;
  system_->index_sets().persistent = persistent;
  system_->scatter_state(q_, v_);

  bool linear = true;
  for (Index j : persistent) linear = linear && system_->interaction(j).relation().is_linear();
  free_flight_ = !system_->has_force() && linear;
  if (motion_->dense) motion_->dense->invalidate();
}

}  // namespace mimpact::plugins
