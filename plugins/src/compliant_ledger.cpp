#include <algorithm>

#include "compliant_state.hpp"
#include "mimpact/plugins/compliant_integrator.hpp"

// The compliant contacts' force and energy on their loading and unloading curves, and the energy
// ledger: each contact's work and the forces' work, accounted at the segment ends
// (docs/model.md, section 12).
namespace mimpact::plugins {

using compliant::Body;
using compliant::Contact;
using compliant::linear_gap;
using kernel::Index;
using kernel::VectorXd;

double CompliantIntegrator::contact_energy(std::size_t j, double delta) const {
  return numerics::hysteresis_energy(laws_[j], delta, max_compression_[j]);
}

double CompliantIntegrator::contact_force(std::size_t j, double delta) const {
  return numerics::hysteresis_force(laws_[j], delta, max_compression_[j]);
}

// The ledger's accounting points are the segment ends: over any part of a Dormand-Prince step
// (its dense output included) the velocities change by M^-1 (W dP + dP_forces) with the same
// weights as the integrated impulses, so the trapezoidal rule on u_j and v gives the kinetic
// energy's change exactly: dT = sum_j u_j_mean dP_j + v_mean . F dt, the forces taken constant
// over the step (the precompression is). Linear relations only: W is then constant.
void CompliantIntegrator::start_accounting() {
  State& s = *state_;
  if (!s.linear) return;
  const std::size_t impulses = 2 * std::size_t(s.motion.coordinates);
  for (Index j : s.motion.joined) {
    Contact& c = s.contact(j);
    double gap;
    linear_gap(s, c, time_, s.y.data(), gap, c.accounted_rate);
    c.accounted_impulse = s.y[impulses + std::size_t(c.slot)];
  }
  s.ledger.accounted_velocity.assign(s.y.begin() + s.motion.coordinates, s.y.begin() + impulses);
  s.ledger.accounted_time = time_;
}

void CompliantIntegrator::account_work(double t) {
  State& s = *state_;
  if (!s.linear) return;
  const Index n = s.motion.coordinates;
  for (Index j : s.motion.joined) {
    Contact& c = s.contact(j);
    double gap, rate;
    linear_gap(s, c, t, s.y.data(), gap, rate);
    const double impulse = s.y[std::size_t(2 * n + c.slot)];
    history_.work(j) -= 0.5 * (c.accounted_rate + rate) * (impulse - c.accounted_impulse);
    c.accounted_rate = rate;
    c.accounted_impulse = impulse;
  }
  for (Index k : s.motion.moving) {
    Body& b = s.body(k);
    if (!b.has_force) continue;
    b.q = s.anchor_q.segment(b.offset, b.size) + Eigen::Map<const VectorXd>(&s.y[b.slot], b.size);
    b.v = Eigen::Map<const VectorXd>(&s.y[n + b.slot], b.size);
    system_->system(k).force(t, b.q, b.v, b.force);
    for (Index i = 0; i < b.size; ++i) {
      double& before = s.ledger.accounted_velocity[std::size_t(b.slot + i)];
      history_.work_of_forces +=
          0.5 * (before + b.v(i)) * b.force(i) * (t - s.ledger.accounted_time);
      before = b.v(i);
    }
  }
  s.ledger.accounted_time = t;
  account_slip();
}

void CompliantIntegrator::update_stored_energy() {
  State& s = *state_;
  history_.stored_energy.setZero();
  for (Index j : s.motion.joined) {
    double gap = s.contact(j).anchor_gap, rate;
    if (s.linear) linear_gap(s, s.contact(j), time_, s.y.data(), gap, rate);
    history_.stored_energy(j) = contact_energy(std::size_t(j), -gap);
  }
}

}  // namespace mimpact::plugins
