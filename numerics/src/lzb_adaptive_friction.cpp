#include "lzb_adaptive_friction.hpp"

namespace mimpact::numerics::adaptive_lzb {

using Eigen::Index;
using Sparse = Eigen::SparseMatrix<double>;

using coulomb::norm;

void Friction::prepare(const ImpactIntegrator::Input& input) {
  on_ = input.laws.frictional();
  members_.clear();
  previous_.clear();
  slots_.clear();
  if (!on_) return;
  rows_ = input.tangential;
  tangent_to_normal_ = input.tangent_to_normal;
  const std::size_t m = input.laws.size();
  mu_.resize(m);
  for (std::size_t j = 0; j < m; ++j) mu_[j] = input.laws.friction(j);
  contacts_.assign(m, {});
  impulse_.assign(std::size_t(rows_->rows()), 0.0);
  slot_of_row_.assign(std::size_t(rows_->rows()), -1);
}

void Friction::add_reached() {
  Segment& segment = impact_.segment;
  std::vector<int>& member_of = impact_.contact.member_of;
  for (std::size_t a = 0; a < segment.active; ++a) {
    const Index j = segment.members[a];
    if (!(mu_[std::size_t(j)] > 0.0)) continue;
    for (Index r = rows_->first_row[std::size_t(j)]; r < rows_->first_row[std::size_t(j) + 1]; ++r)
      for (Sparse::InnerIterator it(*tangent_to_normal_, r); it; ++it)
        if (member_of[std::size_t(it.row())] < 0) {
          member_of[std::size_t(it.row())] = int(segment.members.size());
          segment.members.push_back(it.row());
        }
  }
}

void Friction::size_segment() {
  const Segment& segment = impact_.segment;
  for (const Slot& slot : slots_) slot_of_row_[std::size_t(slot.row)] = -1;
  for (Index j : previous_)  // out of the impact since: its mode is chosen again when it returns
    if (const int p = impact_.contact.member_of[std::size_t(j)];
        p < 0 || std::size_t(p) >= segment.active)
      contacts_[std::size_t(j)].phase.mode = Mode::choose;
  members_.clear();
  slots_.clear();
  previous_.clear();
  for (std::size_t a = 0; a < segment.active; ++a) {
    const Index j = segment.members[a];
    const int rows = rows_->rows_of(j);
    if (!(mu_[std::size_t(j)] > 0.0) || rows == 0) continue;
    const Index row = rows_->first_row[std::size_t(j)];
    members_.push_back({a, j, row, rows, slots_.size()});
    previous_.push_back(j);
    for (int k = 0; k < rows; ++k) {
      slot_of_row_[std::size_t(row + k)] = int(slots_.size());
      slots_.push_back({.row = row + k, .member = members_.size() - 1});
    }
  }
  base_ = 2 * segment.active;
  impact_.segment.y.resize(base_ + slots_.size(), 0.0);
  impact_.segment.y_at.resize(base_ + slots_.size(), 0.0);
  // s at the start: s- + H_tn P + H_tt P_t over the impact so far (rows of H_tn^T, of H_tt)
  for (Slot& slot : slots_) {
    double s = rows_->slip_minus(slot.row);
    for (Sparse::InnerIterator it(*tangent_to_normal_, slot.row); it; ++it)
      s += it.value() * impact_.contact.impulse[std::size_t(it.row())];
    for (Sparse::InnerIterator it(rows_->tangent, slot.row); it; ++it)
      s += it.value() * impulse_[std::size_t(it.row())];
    slot.start = slot.accounted_slip = s;
  }
  scratch_.forces.resize(segment.active);
  scratch_.slips.resize(slots_.size());
  scratch_.rates.resize(slots_.size());
  choose_modes();
}

// Slip where |s| > tolerance * V; else stick, unless the force that keeps the rows stuck is
// outside the cone: then the contact whose force is furthest outside slips where it points,
// and the others are tried again (the active-set rule of a planar frictional impact, Stronge
// 2000: a slip that stops sticks or reverses).
void Friction::choose_modes() {
  const double tolerance = impact_.velocity_tolerance;
  for (const Member& f : members_) {
    coulomb::Phase& phase = contacts_[std::size_t(f.contact)].phase;
    if (phase.mode != Mode::choose) continue;
    const double s[2] = {slots_[f.slot].start, f.rows == 2 ? slots_[f.slot + 1].start : 0.0};
    phase.start(s, f.rows, tolerance);
  }
  const State& y = impact_.segment.y;  // the segment's start
  normal_forces(y, true);
  coulomb::settle_sticks(
      [&] {
        factor_stick();
        slips(y);
        rates();
      },
      [&](auto&& visit) {
        for (const Member& f : members_)
          visit(contacts_[std::size_t(f.contact)].phase, &scratch_.rates[f.slot], f.rows,
                mu_[std::size_t(f.contact)] * scratch_.forces[f.active]);
      });
}

void Friction::factor_stick() {
  stick_slots_.clear();
  for (Slot& slot : slots_) slot.stick = -1;
  for (const Member& f : members_)
    if (contacts_[std::size_t(f.contact)].phase.mode == Mode::stick)
      for (int k = 0; k < f.rows; ++k) {
        slots_[f.slot + std::size_t(k)].stick = int(stick_slots_.size());
        stick_slots_.push_back(f.slot + std::size_t(k));
      }
  const Index n = Index(stick_slots_.size());
  scratch_.stick_rhs.resize(n);
  if (n == 0) return;
  Eigen::MatrixXd block = Eigen::MatrixXd::Zero(n, n);
  for (Index i = 0; i < n; ++i)
    for (Sparse::InnerIterator it(rows_->tangent, slots_[stick_slots_[std::size_t(i)]].row); it;
         ++it)
      if (const int slot = slot_of_row_[std::size_t(it.row())]; slot >= 0)
        if (const int k = slots_[std::size_t(slot)].stick; k >= 0) block(k, i) = it.value();
  stick_factor_.compute(block);
}

double Friction::scale(std::size_t slot) const {
  return impact_.law.impulse_scale[std::size_t(members_[slots_[slot].member].contact)];
}

void Friction::normal_forces(const State& y, bool start) {
  const Segment& segment = impact_.segment;
  for (std::size_t a = 0; a < segment.active; ++a) {
    const Index j = segment.members[a];
    double force = impact_.law.force(j, impact_.delta_of(a, y));
    const double u = impact_.contact.velocity[std::size_t(j)];
    if (start && force == 0.0 && u < 0.0) {
      const double fastest =
          impact_.law.impulse_scale[std::size_t(j)] * impact_.law.self_mobility[std::size_t(j)];
      force = impact_.law.force(j, 1e-6 * impact_.law.delta_scale[std::size_t(j)] * -u / fastest);
    }
    scratch_.forces[a] = force;
  }
}

void Friction::slips(const State& y) {
  const Segment& segment = impact_.segment;
  for (std::size_t q = 0; q < slots_.size(); ++q) scratch_.slips[q] = slots_[q].start;
  for (std::size_t a = 0; a < segment.active; ++a) {
    const Index j = segment.members[a];
    const double increment = y[segment.active + a] * impact_.law.impulse_scale[std::size_t(j)];
    if (increment == 0.0) continue;
    for (Sparse::InnerIterator it(rows_->normal_to_tangent, j); it; ++it)
      if (const int slot = slot_of_row_[std::size_t(it.row())]; slot >= 0)
        scratch_.slips[std::size_t(slot)] += it.value() * increment;
  }
  for (std::size_t q = 0; q < slots_.size(); ++q) {
    const double increment = y[base_ + q] * scale(q);
    if (increment == 0.0) continue;
    for (Sparse::InnerIterator it(rows_->tangent, slots_[q].row); it; ++it)
      if (const int slot = slot_of_row_[std::size_t(it.row())]; slot >= 0)
        scratch_.slips[std::size_t(slot)] += it.value() * increment;
  }
}

void Friction::rates() {
  for (const Member& f : members_) {
    const coulomb::Phase& phase = contacts_[std::size_t(f.contact)].phase;
    if (phase.mode != Mode::slip) continue;
    phase.slip_force(mu_[std::size_t(f.contact)] * scratch_.forces[f.active],
                     &scratch_.slips[f.slot], f.rows, &scratch_.rates[f.slot]);
  }
  if (stick_slots_.empty()) return;
  // H_tt[S,S] x = -(H_tn[S,:] F + H_tt[S,slip] f_slip): ds/dt = 0 on the sticking rows
  Eigen::VectorXd& rhs = scratch_.stick_rhs;
  rhs.setZero();
  const Segment& segment = impact_.segment;
  for (std::size_t a = 0; a < segment.active; ++a) {
    if (scratch_.forces[a] == 0.0) continue;
    for (Sparse::InnerIterator it(rows_->normal_to_tangent, segment.members[a]); it; ++it)
      if (const int slot = slot_of_row_[std::size_t(it.row())]; slot >= 0)
        if (const int i = slots_[std::size_t(slot)].stick; i >= 0)
          rhs(i) -= it.value() * scratch_.forces[a];
  }
  for (std::size_t q = 0; q < slots_.size(); ++q) {
    if (slots_[q].stick >= 0 || scratch_.rates[q] == 0.0) continue;
    for (Sparse::InnerIterator it(rows_->tangent, slots_[q].row); it; ++it)
      if (const int slot = slot_of_row_[std::size_t(it.row())]; slot >= 0)
        if (const int i = slots_[std::size_t(slot)].stick; i >= 0)
          rhs(i) -= it.value() * scratch_.rates[q];
  }
  const Eigen::VectorXd x = stick_factor_.solve(rhs);
  for (std::size_t i = 0; i < stick_slots_.size(); ++i)
    scratch_.rates[stick_slots_[i]] = x(Index(i));
}

void Friction::push_normal(const State& y, std::vector<double>& velocity) const {
  for (std::size_t q = 0; q < slots_.size(); ++q) {
    const double increment = y[base_ + q] * scale(q);
    if (increment == 0.0) continue;
    for (Sparse::InnerIterator it(*tangent_to_normal_, slots_[q].row); it; ++it)
      if (const int p = impact_.contact.member_of[std::size_t(it.row())]; p >= 0)
        velocity[std::size_t(p)] += it.value() * increment;
  }
}

double Friction::normal_increment(const State& y, Index j) const {
  double increment = 0.0;
  for (Sparse::InnerIterator it(rows_->normal_to_tangent, j); it; ++it)
    if (const int slot = slot_of_row_[std::size_t(it.row())]; slot >= 0)
      increment += it.value() * y[base_ + std::size_t(slot)] * scale(std::size_t(slot));
  return increment;
}

void Friction::derivative(const State& y, State& dydt) {
  normal_forces(y, false);
  slips(y);
  rates();
  for (std::size_t q = 0; q < slots_.size(); ++q) dydt[base_ + q] = scratch_.rates[q] / scale(q);
}

std::array<double, 2> Friction::values_of(const Member& f) const {
  return contacts_[std::size_t(f.contact)].phase.watched(
      mu_[std::size_t(f.contact)] * scratch_.forces[f.active], &scratch_.slips[f.slot],
      &scratch_.rates[f.slot], f.rows, impact_.velocity_tolerance);
}

void Friction::watch(const State& y, std::vector<double>& values) {
  normal_forces(y, false);
  slips(y);
  rates();
  values.resize(2 * members_.size());
  for (std::size_t f = 0; f < members_.size(); ++f) {
    const std::array<double, 2> q = values_of(members_[f]);
    values[2 * f] = q[0];
    values[2 * f + 1] = q[1];
  }
}

double Friction::value(std::size_t member, int which, const State& y) {
  normal_forces(y, false);
  slips(y);
  rates();
  return values_of(members_[member])[std::size_t(which)];
}

void Friction::locate(double t0, double t1, double segment_start, const std::vector<double>& before,
                      const std::vector<double>& after, std::vector<Crossing>& found) {
  for (std::size_t f = 0; f < members_.size(); ++f)
    for (int which = 0; which < 2; ++which) {
      auto q = [&](double t) {
        ode_.state_at(t, impact_.segment.y_at);
        return value(f, which, impact_.segment.y_at);
      };
      const std::optional<double> crossing =
          crossing_time(before[2 * f + std::size_t(which)], after[2 * f + std::size_t(which)], t0,
                        t1, segment_start, q);
      if (!crossing) continue;
      const bool stuck = contacts_[std::size_t(members_[f].contact)].phase.mode == Mode::stick;
      const int kind = which == 1 ? slip_armed : stuck ? stick_end : slip_stop;
      found.push_back({long(f), kind, *crossing});
    }
}

void Friction::apply(const Crossing& crossing) {
  contacts_[std::size_t(members_[std::size_t(crossing.index)].contact)].phase.pass(crossing.kind ==
                                                                                   stick_end);
}

void Friction::account_work(const State& y) {
  slips(y);
  for (std::size_t q = 0; q < slots_.size(); ++q) {
    Slot& slot = slots_[q];
    const double impulse = y[base_ + q] * scale(q);
    contacts_[std::size_t(members_[slot.member].contact)].slip_work -=
        0.5 * (slot.accounted_slip + scratch_.slips[q]) * (impulse - slot.accounted_impulse);
    slot.accounted_slip = scratch_.slips[q];
    slot.accounted_impulse = impulse;
  }
}

void Friction::end_segment(const State& y) {
  for (std::size_t q = 0; q < slots_.size(); ++q)
    impulse_[std::size_t(slots_[q].row)] += y[base_ + q] * scale(q);
}

double Friction::tangential_impulse(Eigen::Index row, const State* y) const {
  const int q = slot_of_row_[std::size_t(row)];
  double impulse = impulse_[std::size_t(row)];
  if (y && q >= 0) impulse += (*y)[base_ + std::size_t(q)] * scale(std::size_t(q));
  return impulse;
}

void Friction::finish(ImpactResult& result) const {
  result.tangential_impulse =
      Eigen::Map<const Eigen::VectorXd>(impulse_.data(), Index(impulse_.size()));
  result.slip_work.resize(Index(contacts_.size()));
  for (std::size_t j = 0; j < contacts_.size(); ++j)
    result.slip_work(Index(j)) = contacts_[j].slip_work;
}

}  // namespace mimpact::numerics::adaptive_lzb
