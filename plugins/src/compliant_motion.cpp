#include <algorithm>
#include <cmath>

#include "compliant_state.hpp"
#include "mimpact/plugins/compliant_integrator.hpp"

// The moving-body set of the compliant integrator (docs/design/compliant_contacts.md): the
// right-hand side of its motion, which bodies are integrated and which fly freely, the contacts
// that join and leave, the joins computed in closed form between bodies in free flight.
namespace mimpact::plugins {

using compliant::Body;
using compliant::Contact;
using compliant::GapSamples;
using compliant::JacobianEntry;
using compliant::linear_gap;
using kernel::Index;
using kernel::VectorXd;

void CompliantIntegrator::evaluate(double t, const double* y, double* dydt) {
  State& s = *state_;
  const Index n = s.motion.coordinates;
  s.scratch.generalized.setZero();
  if (!s.linear) {  // every body moves: the whole configuration
    for (Index k : s.motion.moving) {
      const Body& b = s.body(k);
      for (Index i = 0; i < b.size; ++i) {
        s.scratch.q_all(b.offset + i) = s.anchor_q(b.offset + i) + y[b.slot + i];
        s.scratch.v_all(b.offset + i) = y[n + b.slot + i];
      }
    }
  }
  for (Index j : s.motion.joined) {
    const Contact& c = s.contact(j);
    double gap, rate;
    if (s.linear) {
      linear_gap(s, c, t, y, gap, rate);
    } else {
      gap = system_->gap(j, s.scratch.q_all);
    }
    const double f = contact_force(std::size_t(j), -gap);
    dydt[2 * n + c.slot] = f;
    if (f == 0.0) continue;
    if (s.linear) {
      for (const JacobianEntry& entry : c.entries)
        s.scratch.generalized(s.body(entry.body).slot + entry.local) += entry.value * f;
    } else {
      system_->for_each_jacobian_entry(j, s.scratch.q_all, [&](Index coordinate, double value) {
        const Body& b = s.body(s.body_of_coordinate[std::size_t(coordinate)]);
        s.scratch.generalized(b.slot + s.local_of_coordinate[std::size_t(coordinate)]) += value * f;
      });
    }
  }
  const bool rubbing = !s.friction.rubbing.empty();
  if (rubbing) add_tangential_forces(t, y, dydt);
  for (Index k : s.motion.moving) {
    Body& b = s.body(k);
    b.q = s.anchor_q.segment(b.offset, b.size) + Eigen::Map<const VectorXd>(y + b.slot, b.size);
    b.v = Eigen::Map<const VectorXd>(y + n + b.slot, b.size);
    b.refresh(system_->system(k), b.q);
    Eigen::Map<VectorXd> acceleration(dydt + n + b.slot, b.size);
    acceleration = s.scratch.generalized.segment(b.slot, b.size);
    if (b.has_force) {
      system_->system(k).force(t, b.q, b.v, b.force);
      acceleration += b.force;
    }
    b.apply_inverse(acceleration);
    Eigen::Map<VectorXd>(dydt + b.slot, b.size) = b.v;
  }
  if (rubbing) tangential_rates(dydt);
}

void CompliantIntegrator::commit_motion() {
  State& s = *state_;
  for (Index k : s.motion.moving) {
    Body& b = s.body(k);
    for (Index i = 0; i < b.size; ++i) {
      const double d = s.y[std::size_t(b.slot + i)];
      s.anchor_q(b.offset + i) += d;
      s.anchor_v(b.offset + i) = s.y[std::size_t(s.motion.coordinates + b.slot + i)];
      if (!s.linear || d == 0.0) continue;
      for (Index j : system_->interactions_of(k))
        for (const JacobianEntry& entry : s.contact(j).entries)
          if (entry.body == k && entry.local == i) s.contact(j).anchor_gap += entry.value * d;
    }
    b.anchor_time = time_;
  }
  const std::size_t impulses = 2 * std::size_t(s.motion.coordinates);
  for (Index j : s.motion.joined) {
    Contact& c = s.contact(j);
    c.impulse += s.y[impulses + std::size_t(c.slot)];
    history_.impulse(j) = c.impulse;
  }
  commit_friction();
}

void CompliantIntegrator::set_in_motion(Index k) {
  State& s = *state_;
  Body& b = s.body(k);
  if (b.in_motion) return;
  fold_flight(k);
  b.in_motion = true;
  s.motion.moving.push_back(k);
  for (Index j : system_->interactions_of(k)) forget_prediction(j);
}

// A body in free flight: its flight up to now folded into its anchor.
void CompliantIntegrator::fold_flight(Index k) {
  State& s = *state_;
  Body& b = s.body(k);
  if (b.in_motion) return;  // anchored by the last commit
  for (Index i = 0; i < b.size; ++i) {
    const double d = s.anchor_v(b.offset + i) * (time_ - b.anchor_time);
    s.anchor_q(b.offset + i) += d;
    if (!s.linear || d == 0.0) continue;
    for (Index j : system_->interactions_of(k))
      for (const JacobianEntry& entry : s.contact(j).entries)
        if (entry.body == k && entry.local == i) s.contact(j).anchor_gap += entry.value * d;
  }
  b.anchor_time = time_;
}

void CompliantIntegrator::set_free(Index k) {
  State& s = *state_;
  Body& b = s.body(k);
  if (!b.in_motion || !b.can_fly || b.loaded_contacts > 0) return;
  b.in_motion = false;
  std::erase(s.motion.moving, k);
  for (Index j : system_->interactions_of(k)) predict_join(j);
}

void CompliantIntegrator::join(Index j) {
  State& s = *state_;
  Contact& c = s.contact(j);
  c.joined = true;
  c.has_closed = true;
  s.motion.joined.push_back(j);
  forget_prediction(j);
  for (Index k : {system_->first_system(j), system_->second_system(j)})
    if (k >= 0) {
      ++s.body(k).loaded_contacts;
      set_in_motion(k);
    }
}

void CompliantIntegrator::leave(Index j) {
  State& s = *state_;
  s.contact(j).joined = false;
  compliant::Rub& rub = s.contact(j).rub;  // its phase chosen again if it joins again, its
  rub.phase = {};                          // spring born again
  rub.spring = {};
  rub.stretch = {0.0, 0.0};
  std::erase(s.motion.joined, j);
  max_compression_[std::size_t(j)] = 0.0;  // the contact forgets
  history_.force(j) = 0.0;
  for (Index k : {system_->first_system(j), system_->second_system(j)})
    if (k >= 0) {
      --s.body(k).loaded_contacts;
      set_free(k);
    }
}

// Between bodies in free flight the gap is linear in time: the join is where it reaches
// -join_overlap.
void CompliantIntegrator::predict_join(Index j) {
  State& s = *state_;
  Contact& c = s.contact(j);
  if (!s.linear || c.joined || c.predicted) return;
  double gap = c.anchor_gap, rate = 0.0;
  for (const JacobianEntry& entry : c.entries) {
    const Body& b = s.body(entry.body);
    if (b.in_motion) return;  // watched along the integration instead
    const double v = s.anchor_v(b.offset + entry.local);
    gap += entry.value * v * (time_ - b.anchor_time);
    rate += entry.value * v;
  }
  if (!(rate < 0.0)) return;
  if (options_.frozen_gaps && c.has_closed && gap > s.leave_overlap) {
    c.anchor_gap -= gap;  // it approaches again (turned by a collision): its gap is forgotten
    gap = 0.0;
  }
  const double time = time_ + std::max(0.0, (gap + s.join_overlap) / -rate);
  s.motion.predictions.push({time, j, c.version});
  c.predicted = true;
  ++s.motion.pending_predictions;
}

void CompliantIntegrator::forget_prediction(Index j) {
  State& s = *state_;
  Contact& c = s.contact(j);
  ++c.version;
  if (!c.predicted) return;
  c.predicted = false;
  --s.motion.pending_predictions;
}

// Behind a wave, bodies left at rest against each other approach with speeds of the order of
// the integration's own errors. Such a collision changes the velocities by less than the
// tolerance, and its largest overlap lies below what the error control resolves, so that
// integrating it would only feed those errors (and keep ever more bodies in motion). A collision
// is therefore taken as instantaneous, u+ = -e u- by the impulse P = -(1 + e) u- / H_jj, the
// outcome of an isolated pair, when it approaches slower than relative_tolerance x the fastest
// initial speed, or slower than an isolated pair whose largest overlap is the joining overlap
// delta_res: K delta_res^(1 + eta) / (1 + eta) = u-^2 / (2 H_jj). Integrated, such a contact
// would join at delta_res under a force its approach never paid for, and leave faster than it
// came. Linear relations and constant diagonal masses only; the ledger books its work
// -(u- + u+) P / 2, exactly what the kinetic energy loses.
bool CompliantIntegrator::collide_instantly(Index j) {
  State& s = *state_;
  Contact& c = s.contact(j);
  if (!s.linear || c.rub.rows > 0) return false;  // a contact that rubs is integrated
  double rate = 0.0, h = 0.0;
  for (const JacobianEntry& entry : c.entries) {
    Body& b = s.body(entry.body);
    if (!b.diagonal || !b.constant) return false;
    if (!b.factorized) {
      b.q = s.anchor_q.segment(b.offset, b.size);
      b.refresh(system_->system(entry.body), b.q);
    }
    rate += entry.value * s.anchor_v(b.offset + entry.local);
    h += entry.value * entry.value * b.inverse_diagonal(entry.local);
  }
  const numerics::ContactLaw& law = laws_[std::size_t(j)];
  const double turns_below_resolution =
      std::sqrt(2.0 * h * law.stiffness * std::pow(s.join_overlap, 1.0 + law.exponent) /
                (1.0 + law.exponent));
  if (!(rate < 0.0 && -rate < std::max(slow_speed_, turns_below_resolution))) return false;
  for (Index k : {system_->first_system(j), system_->second_system(j)})
    if (k >= 0) fold_flight(k);
  const double e = laws_[std::size_t(j)].restitution;
  const double impulse = -(1.0 + e) * rate / h;
  for (const JacobianEntry& entry : c.entries) {
    const Body& b = s.body(entry.body);
    s.anchor_v(b.offset + entry.local) += b.inverse_diagonal(entry.local) * entry.value * impulse;
  }
  c.impulse += impulse;
  history_.impulse(j) = c.impulse;
  history_.work(j) -= 0.5 * (rate - e * rate) * impulse;
  // the velocities changed: the joins of every contact of the two bodies, computed again
  for (Index k : {system_->first_system(j), system_->second_system(j)})
    if (k >= 0)
      for (Index other : system_->interactions_of(k)) {
        forget_prediction(other);
        predict_join(other);
      }
  return true;
}

// The earliest join computed between bodies in free flight in [a, b], its stale predictions
// (of contacts whose motion changed since) dropped.
bool CompliantIntegrator::next_predicted_join(double a, double b, Event& event) {
  State& s = *state_;
  while (!s.motion.predictions.empty() && s.motion.predictions.top().version !=
                                              s.contact(s.motion.predictions.top().contact).version)
    s.motion.predictions.pop();
  if (s.motion.predictions.empty() || s.motion.predictions.top().time > b) return false;
  event = {s.motion.predictions.top().contact, numerics::ContactEvent::joining,
           std::max(a, s.motion.predictions.top().time)};
  return true;
}

}  // namespace mimpact::plugins
