#include <algorithm>
#include <cmath>

#include "compliant_state.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/numerics/dense_output.hpp"
#include "mimpact/numerics/root_bracketing.hpp"
#include "mimpact/plugins/compliant_integrator.hpp"

// Coulomb's law on the compliant contacts that rub, with a rigid tangential response
// (docs/friction.md, section 2): a joined contact with friction mu > 0 carries its tangential
// impulse P_t (one row in the plane, two in space) in the integrated state, with
// dP_t/dt = f_t its numerics::coulomb::Phase gives from its normal force f_n = dP_n/dt and its
// slip s = W_t^T v: -mu f_n d while it slips, and while it sticks the force that keeps ds/dt = 0,
//   H_tt[S,S] f_S = -W_t[S]^T a,   a = M^-1 (F + W f_n + W_t f_slip),   H_tt = W_t^T M^-1 W_t,
// on the sticking rows S together. Its switches are located events that restart the
// integration, so that no step crosses one. With W and W_t constant this is the adaptive LZB
// impact's ODE with time for its variable: in the frozen configuration at e = 1 the two meet.
// A contact whose law has a tangential stiffness (lambda > 0) carries a Mindlin spring instead
// (numerics::mindlin::Spring): its stretch follows it in the integrated state after the
// tangential impulses, its force is explicit, and its switches are located events too.
namespace mimpact::plugins {

using compliant::Body;
using compliant::Contact;
using compliant::JacobianEntry;
using compliant::Rub;
using kernel::Index;
using kernel::MatrixXd;
using kernel::VectorXd;
using Mode = numerics::coulomb::Phase::Mode;

namespace {

// kind of a Coulomb switch among the contact events' kinds of a scan: past every ContactEvent
constexpr int kCoulombSwitch = 1 << 8;

// the slip along one tangent row (m/s) with the integrated state y
double row_slip(const compliant::State& s, const std::vector<JacobianEntry>& row, const double* y) {
  double slip = 0.0;
  for (const JacobianEntry& entry : row)
    slip += entry.value * s.velocity(s.bodies[std::size_t(entry.body)], entry.local, y);
  return slip;
}

}  // namespace

numerics::mindlin::Terms CompliantIntegrator::spring_terms(Index j, double t,
                                                           const double* y) const {
  const Contact& c = state_->contact(j);
  double gap, rate;
  compliant::linear_gap(*state_, c, t, y, gap, rate);
  return numerics::mindlin::terms(c.rub.spring_ratio, laws_[std::size_t(j)].exponent, c.rub.mu,
                                  contact_force(std::size_t(j), -gap), -gap, -rate);
}

int CompliantIntegrator::coulomb_switch(int kind) {
  return kind >= kCoulombSwitch ? kind - kCoulombSwitch : -1;
}

void CompliantIntegrator::prepare_friction() {
  State& s = *state_;
  const Index m = system_->interaction_count();
  std::vector<Index> all(static_cast<std::size_t>(m));
  for (Index j = 0; j < m; ++j) all[std::size_t(j)] = j;
  std::vector<Index> first_row;
  const Eigen::SparseMatrix<double> tangents = system_->tangent_matrix(all, s.anchor_q, first_row);
  for (Index j = 0; j < m; ++j) {
    const double mu = laws_[std::size_t(j)].friction;
    const int rows = int(first_row[std::size_t(j) + 1] - first_row[std::size_t(j)]);
    if (!(mu > 0.0) || rows == 0) continue;
    if (!s.linear)
      throw InvalidInput(invalid_value_message(
          "friction", mu,
          "0 in the compliant integrator unless every relation is linear (interaction '" +
              system_->interaction(j).name() + "' rubs along rows that move)"));
    Rub& rub = s.contact(j).rub;
    rub.rows = rows;
    rub.mu = mu;
    rub.spring_ratio = laws_[std::size_t(j)].tangential_stiffness_ratio;
    if (rub.spring_ratio > 0.0 && laws_[std::size_t(j)].restitution != 1.0)
      throw InvalidInput(invalid_value_message(
          "tangential_stiffness_ratio", rub.spring_ratio,
          "0 for a contact of restitution " + to_text(laws_[std::size_t(j)].restitution) + " ('" +
              system_->interaction(j).name() +
              "'): the Mindlin spring is integrated for elastic contacts, e = 1"));
    for (int k = 0; k < rows; ++k)
      for (Eigen::SparseMatrix<double>::InnerIterator it(tangents, first_row[std::size_t(j)] + k);
           it; ++it) {
        const Index coordinate = it.row();
        rub.tangents[std::size_t(k)].push_back({s.body_of_coordinate[std::size_t(coordinate)],
                                                s.local_of_coordinate[std::size_t(coordinate)],
                                                it.value()});
      }
    for (Index k : {system_->first_system(j), system_->second_system(j)})
      if (k >= 0 && !s.body(k).constant)
        throw InvalidInput(invalid_value_message(
            "friction", mu,
            "0 in the compliant integrator for a body whose mass depends on its configuration ('" +
                system_->system(k).name() + "')"));
    s.friction.on = true;
  }
  if (!s.friction.on) return;
  history_.tangential_impulse.setZero(m, 2);
  history_.slip_work.setZero(m);
  s.friction.slip_tolerance = slow_speed_;
}

// The rubbing contacts' slots after the normal impulses, their phases chosen where they are new
// or past a switch: slip where |s| > the slip tolerance, else stick while the force that keeps
// them is within their cones (the sticking contact furthest outside slips against its force,
// and the forces are found again).
void CompliantIntegrator::restart_friction() {
  State& s = *state_;
  State::Friction& f = s.friction;
  f.rubbing.clear();
  f.first_slot = Index(s.y.size());
  f.slots = 0;
  for (Index j : s.motion.joined)
    if (Rub& rub = s.contact(j).rub; rub.rows > 0) {
      f.rubbing.push_back(j);
      rub.slot = f.first_slot + f.slots;
      f.slots += rub.rows;
    }
  f.segment_start = time_;
  if (f.rubbing.empty()) return;
  Index stretches = 0;
  for (Index j : f.rubbing)
    if (Rub& rub = s.contact(j).rub; rub.spring_ratio > 0.0) {
      rub.stretch_slot = f.first_slot + f.slots + stretches;
      stretches += rub.rows;
    }
  s.y.resize(s.y.size() + std::size_t(f.slots + stretches), 0.0);
  f.slip.assign(std::size_t(f.slots), 0.0);
  f.force = f.slip;
  f.dydt.resize(s.y.size());
  for (Index j : f.rubbing) {
    Rub& rub = s.contact(j).rub;
    double slip[2] = {0.0, 0.0};
    for (int k = 0; k < rub.rows; ++k)
      slip[k] = row_slip(s, rub.tangents[std::size_t(k)], s.y.data());
    if (rub.spring_ratio > 0.0) {
      rub.spring.start(rub.stretch.data(), slip, rub.rows, spring_terms(j, time_, s.y.data()));
      std::copy_n(rub.stretch.begin(), rub.rows, s.y.begin() + rub.stretch_slot);
    } else if (rub.phase.mode == Mode::choose) {
      rub.phase.start(slip, rub.rows, f.slip_tolerance);
    }
    rub.accounted_impulse = {0.0, 0.0};
    rub.accounted_slip = {slip[0], slip[1]};
  }
  numerics::coulomb::settle_sticks(
      [&] {
        factor_stick();
        evaluate(time_, s.y.data(), f.dydt.data());
      },
      [&](auto&& visit) {
        for (Index j : f.rubbing) {
          Rub& rub = s.contact(j).rub;
          const double normal = f.dydt[std::size_t(2 * s.motion.coordinates + s.contact(j).slot)];
          visit(rub.phase, &f.dydt[std::size_t(rub.slot)], rub.rows, rub.mu * normal);
        }
      });
}

// H_tt on the sticking rows, W_t^T M^-1 W_t over the bodies two rows share, factorized.
void CompliantIntegrator::factor_stick() {
  State& s = *state_;
  State::Friction& f = s.friction;
  f.sticking.clear();
  for (Index j : f.rubbing)
    if (const Rub& rub = s.contact(j).rub; rub.phase.mode == Mode::stick)
      for (int k = 0; k < rub.rows; ++k) f.sticking.emplace_back(j, k);
  const Index n = Index(f.sticking.size());
  if (n == 0) return;
  auto row = [&](Index i) -> const std::vector<JacobianEntry>& {
    return s.contact(f.sticking[std::size_t(i)].first)
        .rub.tangents[std::size_t(f.sticking[std::size_t(i)].second)];
  };
  MatrixXd block = MatrixXd::Zero(n, n);
  VectorXd column;
  for (Index i = 0; i < n; ++i)
    for (const JacobianEntry& e : row(i)) {
      Body& b = s.body(e.body);
      b.q = s.anchor_q.segment(b.offset, b.size);
      b.refresh(system_->system(e.body), b.q);
      column = VectorXd::Unit(b.size, e.local) * e.value;  // M_b^-1 W_t(i) on body b
      b.apply_inverse(column);
      for (Index k = 0; k < n; ++k)
        for (const JacobianEntry& other : row(k))
          if (other.body == e.body) block(k, i) += other.value * column(other.local);
    }
  f.stick_factor.compute(block);
  f.stick_force.resize(n);
}

void CompliantIntegrator::add_tangential_forces(double t, const double* y, double* dydt) {
  State& s = *state_;
  State::Friction& f = s.friction;
  const Index n = s.motion.coordinates;
  for (Index j : f.rubbing) {
    const Contact& c = s.contact(j);
    const Rub& rub = c.rub;
    double* slip = &f.slip[std::size_t(rub.slot - f.first_slot)];
    double* force = &f.force[std::size_t(rub.slot - f.first_slot)];
    for (int k = 0; k < rub.rows; ++k) {
      slip[k] = row_slip(s, rub.tangents[std::size_t(k)], y);
      force[k] = 0.0;
    }
    if (rub.spring_ratio > 0.0) {
      rub.spring.rates(y + rub.stretch_slot, slip, rub.rows, spring_terms(j, t, y), force,
                       dydt + rub.stretch_slot);
    } else if (rub.phase.mode == Mode::slip) {
      rub.phase.slip_force(rub.mu * dydt[2 * n + c.slot], slip, rub.rows, force);
    } else {
      continue;
    }
    for (int k = 0; k < rub.rows; ++k)
      for (const JacobianEntry& entry : rub.tangents[std::size_t(k)])
        s.scratch.generalized(s.body(entry.body).slot + entry.local) += entry.value * force[k];
  }
}

// The sticking rows' forces, H_tt[S,S] f_S = -W_t[S]^T a, onto the accelerations
// (a += M^-1 W_t[S] f_S); then every rubbing row's dP_t/dt into dydt.
void CompliantIntegrator::tangential_rates(double* dydt) {
  State& s = *state_;
  State::Friction& f = s.friction;
  const Index n = s.motion.coordinates;
  if (!f.sticking.empty()) {
    for (std::size_t i = 0; i < f.sticking.size(); ++i) {
      double rate = 0.0;
      const auto& [j, k] = f.sticking[i];
      for (const JacobianEntry& entry : s.contact(j).rub.tangents[std::size_t(k)])
        rate += entry.value * dydt[n + s.body(entry.body).slot + entry.local];
      f.stick_force(Index(i)) = -rate;
    }
    f.stick_force = f.stick_factor.solve(f.stick_force).eval();
    f.stick_generalized.setZero(n);
    for (std::size_t i = 0; i < f.sticking.size(); ++i) {
      const auto& [j, k] = f.sticking[i];
      const Rub& rub = s.contact(j).rub;
      f.force[std::size_t(rub.slot - f.first_slot + k)] = f.stick_force(Index(i));
      for (const JacobianEntry& entry : rub.tangents[std::size_t(k)])
        f.stick_generalized(s.body(entry.body).slot + entry.local) +=
            entry.value * f.stick_force(Index(i));
    }
    for (Index k : s.motion.moving) {
      const Body& b = s.body(k);
      auto push = f.stick_generalized.segment(b.slot, b.size);
      if (push.isZero(0.0)) continue;
      b.apply_inverse(push);
      Eigen::Map<VectorXd>(dydt + n + b.slot, b.size) += push;
    }
  }
  std::copy(f.force.begin(), f.force.end(), dydt + f.first_slot);
}

void CompliantIntegrator::watch_friction(double t, std::vector<double>& values) {
  State& s = *state_;
  State::Friction& f = s.friction;
  values.resize(2 * f.rubbing.size());
  if (f.rubbing.empty()) return;
  evaluate(t, s.probe.data(), f.dydt.data());
  for (std::size_t r = 0; r < f.rubbing.size(); ++r) {
    const Contact& c = s.contact(f.rubbing[r]);
    const std::size_t slot = std::size_t(c.rub.slot - f.first_slot);
    if (c.rub.spring_ratio > 0.0) {
      values[2 * r] =
          c.rub.spring.watched(&s.probe[std::size_t(c.rub.stretch_slot)], &f.slip[slot], c.rub.rows,
                               spring_terms(f.rubbing[r], t, s.probe.data()));
      values[2 * r + 1] = 1.0;
      continue;
    }
    const double normal = f.dydt[std::size_t(2 * s.motion.coordinates + c.slot)];
    const std::array<double, 2> q = c.rub.phase.watched(
        c.rub.mu * normal, &f.slip[slot], &f.force[slot], c.rub.rows, f.slip_tolerance);
    values[2 * r] = q[0];
    values[2 * r + 1] = q[1];
  }
}

void CompliantIntegrator::locate_switches(double t0, double t1, const std::vector<double>& before,
                                          const std::vector<double>& after,
                                          std::vector<numerics::Crossing>& found) {
  State& s = *state_;
  State::Friction& f = s.friction;
  for (std::size_t r = 0; r < f.rubbing.size(); ++r)
    for (int which = 0; which < 2; ++which) {
      auto value = [&](double t) {
        s.dense->state_at(t, s.probe);
        watch_friction(t, f.values);
        return f.values[2 * r + std::size_t(which)];
      };
      const std::optional<double> crossing = numerics::crossing_time(
          before[2 * r + std::size_t(which)], after[2 * r + std::size_t(which)], t0, t1,
          f.segment_start, value);
      if (crossing) found.push_back({long(f.rubbing[r]), kCoulombSwitch + which, *crossing});
    }
}

// Before the commit: a spring that sticks again is put on its cap in y.
void CompliantIntegrator::pass_switch(const Event& event) {
  State& s = *state_;
  Contact& c = s.contact(event.contact);
  if (c.rub.spring_ratio > 0.0) {
    c.rub.spring.pass(&s.y[std::size_t(c.rub.stretch_slot)], c.rub.rows,
                      spring_terms(event.contact, time_, s.y.data()));
    return;
  }
  numerics::coulomb::Phase& phase = c.rub.phase;
  phase.pass(event.coulomb == 0 && phase.mode == Mode::stick);
}

void CompliantIntegrator::commit_friction() {
  State& s = *state_;
  for (Index j : s.friction.rubbing) {
    Rub& rub = s.contact(j).rub;
    for (int k = 0; k < rub.rows; ++k) {
      rub.impulse[std::size_t(k)] += s.y[std::size_t(rub.slot + k)];
      history_.tangential_impulse(j, k) = rub.impulse[std::size_t(k)];
      if (rub.spring_ratio > 0.0)
        rub.stretch[std::size_t(k)] = s.y[std::size_t(rub.stretch_slot + k)];
    }
  }
}

// The slip's work since the last accounting, by the trapezoidal rule on s (as the normal work).
void CompliantIntegrator::account_slip() {
  State& s = *state_;
  for (Index j : s.friction.rubbing) {
    Rub& rub = s.contact(j).rub;
    for (int k = 0; k < rub.rows; ++k) {
      const double slip = row_slip(s, rub.tangents[std::size_t(k)], s.y.data());
      const double impulse = s.y[std::size_t(rub.slot + k)];
      const double work = -0.5 * (rub.accounted_slip[std::size_t(k)] + slip) *
                          (impulse - rub.accounted_impulse[std::size_t(k)]);
      history_.slip_work(j) += work;
      rub.accounted_slip[std::size_t(k)] = slip;
      rub.accounted_impulse[std::size_t(k)] = impulse;
    }
  }
}

}  // namespace mimpact::plugins
