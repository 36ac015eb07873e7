#include <algorithm>
#include <cmath>

#include "mimpact/numerics/onset_quadrature.hpp"
#include "moving_group.hpp"

// A group's amendments of its steps (docs/design/moving_geometry.md, "A touch within a step"
// and "A turn within a step"): what the step's weights missed of the forces that switched
// within it, and the inelastic contacts' histories turned within it.
namespace mimpact::granular {

// What the step's weights missed of the forces that switched within it, integrated along the
// cubic Hermite of their separation (onset_quadrature.hpp) and added to both ends' velocities,
// equal and opposite, and to the impulse:
// - the elastic Hertz springs between members that closed or opened (`switching`, of the
//   springs, numbered as their impulses in the state); a wall's onsets are a few beads', left;
// - every inelastic spring whose overlap turned, or crossed a corner of its curves (touch,
//   unloading's zero, loading's start at its history): its history turns with it, found here
//   and taken in as the group passes the turn (settle_histories), so that no group restarts
//   for it. Where it turned, its positions are amended too, and the next step forms its first
//   forces anew: an e = 0 contact's force drops to zero there, and the positions' error would
//   be of order h^2.
// Elsewhere only the velocities are amended: the positions' error at an onset, of order h^3.5,
// would take the step's last forces anew (they are the next step's first).
double MovingGroup::amend_switches(const State& start, const State& start_rate, State& end,
                                   const State& end_rate, double h,
                                   std::span<const std::size_t> switching) {
  using numerics::rkn43::nodes, numerics::rkn43::velocity_weights;
  const auto d = std::size_t(dimension_);
  const std::size_t velocities = d * members_.size();
  double* impulses = end.data() + 2 * velocities;
  // A spring whose whole impulse over the step, in the state's units, is under a hundredth of
  // the absolute tolerance changes its beads' velocities by less (their gains T / m are at most
  // the impulses' T / m_lightest), and its weights can miss no more: left as it is (contacts
  // that barely load; docs/design/moving_geometry.md, "A touch within a step").
  const double negligible = 1e-2 * world_.options.ode.absolute_tolerance;
  for (std::size_t j : switching) {
    const Spring& s = springs_.list[j];
    if (s.second < 0 || s.aside >= 0 ||
        std::abs(impulses[j] - start[2 * velocities + j]) < negligible)
      continue;
    const auto a = std::size_t(s.first), b = std::size_t(s.second);
    const Separation s0 = spring_separation(j, start.data(), nullptr, h);
    const Separation s1 = spring_separation(j, end.data(), nullptr, h);
    const Eigen::Vector3d &r0 = s0.r, &u0 = s0.u, &r1 = s1.r, &u1 = s1.u;
    const numerics::OnsetQuadrature missed = numerics::hertz_onset_quadrature(
        {.r0 = r0, .u0 = u0, .r1 = r1, .u1 = u1}, springs_.reach[j], springs_.stiffness[j], nodes,
        velocity_weights);
    for (std::size_t k = 0; k < d; ++k) {
      end[velocities + d * a + k] -= state_.gain[a] * h * missed.impulse(k);
      end[velocities + d * b + k] += state_.gain[b] * h * missed.impulse(k);
    }
    impulses[j] += world_.time_scale / world_.mass_scale * h * missed.magnitude;
  }
  return amend_histories(start, start_rate, end, end_rate, h);
}

// The separation modelled by the quintic Hermite of the step's ends, whose accelerations are the
// law the step took (the cubic places a turn only to O(h^3) in its time:
// docs/design/moving_geometry.md, "Trials not kept").
double MovingGroup::amend_histories(const State& start, const State& start_rate, State& end,
                                    const State& end_rate, double h) {
  using numerics::rkn43::nodes, numerics::rkn43::velocity_weights,
      numerics::rkn43::position_weights;
  const auto d = std::size_t(dimension_);
  const std::size_t velocities = d * members_.size();
  const double leave = 0.5 * world_.options.overlap_resolution;
  double cut = 1.0;
  springs_.history_changes.clear();
  for (const SpringAside& aside : springs_.aside) {
    const ContactState& contact = contacts_[std::size_t(aside.contact)];
    if (contact.law.effective_restitution() >= 1.0) continue;
    const auto j = std::size_t(aside.spring);
    numerics::StepSeparation model{.quintic = true};
    const Separation s0 = spring_separation(j, start.data(), start_rate.data(), h);
    const Separation s1 = spring_separation(j, end.data(), end_rate.data(), h);
    model.r0 = s0.r, model.u0 = s0.u, model.a0 = s0.a;
    model.r1 = s1.r, model.u1 = s1.u, model.a1 = s1.a;
    const double reach = springs_.reach[j], overlap0 = reach - model.r0.norm(),
                 overlap1 = reach - model.r1.norm(), history = contact.max_compression;
    const bool closing0 = model.r0.dot(model.u0) < 0.0, closing1 = model.r1.dot(model.u1) < 0.0;
    auto crosses = [&](double threshold) {
      return (overlap0 > threshold) != (overlap1 > threshold);
    };
    // smooth over the step unless its rate turns or it crosses a corner of its curves
    const double e = contact.law.restitution;
    if (closing0 == closing1 && !crosses(history * (1.0 - e * e)) &&
        !(history > 0.0 && (crosses(history) || crosses(leave))))
      continue;
    const numerics::OnsetQuadrature missed = numerics::contact_step_quadrature(
        model, {.reach = reach, .law = contact.law, .max_compression = history, .opening = leave},
        numerics::StepQuadrature<nodes.size()>{nodes, velocity_weights, position_weights});
    const bool changed = missed.change_count > 0;
    const double share = turn_cut(j, contact.law, missed, overlap1, h);
    if (share < 1.0) {
      cut = std::min(cut, share);
      continue;
    }
    const Spring& s = springs_.list[j];
    auto push = [&](std::size_t slot, double sign) {
      for (std::size_t k = 0; k < d; ++k) {
        end[velocities + d * slot + k] += sign * state_.gain[slot] * h * missed.impulse(k);
        if (changed)
          end[d * slot + k] +=
              sign * state_.gain[slot] * h * h / world_.time_scale * missed.moment(k);
      }
    };
    push(std::size_t(s.first), -1.0);
    if (s.second >= 0) push(std::size_t(s.second), 1.0);
    end[2 * velocities + j] += world_.time_scale / world_.mass_scale * h * missed.magnitude;
    for (std::size_t k = 0; k < missed.change_count; ++k)
      springs_.history_changes.push_back({.spring = std::int32_t(j),
                                          .time = dense_->time() + missed.changes[k].s * h,
                                          .overlap = missed.changes[k].history,
                                          .max_compression = missed.changes[k].history});
    // An e = 0 contact stays at its turn's overlap, at the foot of its loading curve: a rounding
    // deeper would take the loading force again, for a step the error control shortens until
    // its kick is within the tolerance. Its history lies the overlaps' resolution deeper.
    if (changed && springs_.history_changes.back().max_compression > 0.0 &&
        contact.law.effective_restitution() == 0.0)
      springs_.history_changes.back().max_compression += world_.options.overlap_resolution;
  }
  if (cut < 1.0) springs_.history_changes.clear();
  return cut;
}

// After its turn a contact unloads along a curve 1 / e^2 stiffer than the loading the step took,
// and departs from the step's path; the amendment along that path errs by about
// (eta^2 / 30) F_M R^2 tau in impulse, R the path's fall after the turn over e^2 delta_p, tau
// the time after it. Where that would move the lighter body by more than the tolerance times
// the fastest speed (small e, long steps), the step is cut to end just past the turn: the share
// of h it keeps, or 1 (the estimate against a head-on pair: docs/design/moving_geometry.md, "A
// turn within a step"). A turn in the step's last 5 % is amended.
double MovingGroup::turn_cut(std::size_t j, const numerics::ContactLaw& law,
                             const numerics::OnsetQuadrature& missed, double end_overlap,
                             double h) const {
  constexpr double kCutBefore = 0.95, kPastTheTurn = 1.01;
  const auto* const last = missed.changes.begin() + missed.change_count;
  const auto* const turn = std::find_if(missed.changes.begin(), last,
                                        [](const auto& change) { return change.history > 0.0; });
  if (turn == last || turn->s >= kCutBefore) return 1.0;
  const double e = law.restitution, fall = turn->history - std::min(end_overlap, turn->history);
  // (released within the step, R > 1: the unloading lasts tau / sqrt(R), and errs by F_M times
  // that at most; at e = 0 the force drops at once, exactly as amended)
  const double ratio = fall / (e * e * turn->history),
               share = ratio <= 1.0 ? ratio * ratio : 1.0 / std::sqrt(ratio);
  const Spring& s = springs_.list[j];
  const double inverse_mass =  // 1 / kg, the lighter body's
      std::max(state_.gain[std::size_t(s.first)],
               s.second >= 0 ? state_.gain[std::size_t(s.second)] : 0.0) /
      world_.time_scale;
  const double speed_error = law.exponent * law.exponent / 30.0 * law.force(turn->history) * share *
                             (1.0 - turn->s) * h * inverse_mass;
  return speed_error <= world_.options.ode.relative_tolerance * world_.speed_bound
             ? 1.0
             : kPastTheTurn * turn->s;
}

MovingGroup::Separation MovingGroup::spring_separation(std::size_t j, const double* y,
                                                       const double* dydt, double h) const {
  Separation out;
  Eigen::Vector3d &r = out.r, &u = out.u, &a = out.a;
  const auto d = std::size_t(dimension_);
  const std::size_t velocities = d * members_.size();
  // w = T v, w' = T x'': h w / T and h^2 w' / T
  const double to_rate = h * (1.0 / world_.time_scale), to_acceleration = h * to_rate;
  const Spring& s = springs_.list[j];
  const std::size_t first = d * std::size_t(s.first);
  a.setZero();
  if (s.second < 0) {  // from the bead to the wall's plane, along its normal
    double height = springs_.aside[std::size_t(s.aside)].height, speed = 0.0, pull = 0.0;
    for (std::size_t k = 0; k < d; ++k) {
      height += s.offset[k] * y[first + k];
      speed += s.offset[k] * y[velocities + first + k];
      if (dydt) pull += s.offset[k] * dydt[velocities + first + k];
    }
    r = -height * s.offset;
    u = -to_rate * speed * s.offset;
    a = -to_acceleration * pull * s.offset;
    return out;
  }
  const std::size_t second = d * std::size_t(s.second);
  r = s.offset;
  u.setZero();
  for (std::size_t k = 0; k < d; ++k) {
    r(k) += y[second + k] - y[first + k];
    u(k) = to_rate * (y[velocities + second + k] - y[velocities + first + k]);
    if (dydt)
      a(k) = to_acceleration * (dydt[velocities + second + k] - dydt[velocities + first + k]);
  }
  return out;
}

// J: what contact c would give back from where it is, its potential on its curve less, past
// its history on the loading curve, what its last turn booked as dissipated (settle_histories),
// so that kinetic + stored + dissipated stays the energy given, through a reloading too.
double MovingGroup::stored_energy(const Contact& c) {
  const double potential = numerics::hysteresis_energy(c.law, c.compression, c.max_compression);
  if (!(c.max_compression > 0.0) || c.compression < c.max_compression) return potential;
  const double e = c.law.restitution;
  return potential - (1.0 - e * e) * numerics::hysteresis_energy(c.law, c.max_compression, 0.0);
}

// The history changes of the step just taken up to t: where a spring turned, the unloading
// curve from its overlap there, its largest force exactly, and the energy it will not give back
// booked as dissipated, (1 - e^2) of its loading work beyond the history it had (a contact
// that reloads past its history and turns again has given back nothing between); where it
// opened, no history.
void MovingGroup::settle_histories(double t) {
  bool changed = false;
  for (const HistoryChange& change : springs_.history_changes) {
    if (change.time > t) continue;
    const auto j = std::size_t(change.spring);
    Contact& c = contacts_[std::size_t(springs_.active[j])];
    if (change.overlap > 0.0) {
      const double e = c.law.restitution;
      c.dissipated += (1.0 - e * e) * (numerics::hysteresis_energy(c.law, change.overlap, 0.0) -
                                       numerics::hysteresis_energy(c.law, c.max_compression, 0.0));
      const double peak = c.law.force(change.overlap);
      if (peak > springs_.peaks[j].max_force)
        springs_.peaks[j] = {.max_force = peak, .time_of_max = change.time};
    }
    c.max_compression = change.max_compression;
    changed = true;
  }
  springs_.history_changes.clear();
  if (changed) dense_->refresh_derivative();
}

}  // namespace mimpact::granular
