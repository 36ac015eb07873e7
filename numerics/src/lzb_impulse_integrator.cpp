#include "mimpact/numerics/lzb_impulse_integrator.hpp"

#include <algorithm>
#include <cmath>

#include "impact_input.hpp"
#include "impulse_step_rules.hpp"
#include "mimpact/common/error.hpp"

namespace mimpact::numerics {

using Eigen::Index;

using detail::DenseDelassus;
using detail::power_of;
using detail::SparseDelassus;

LzbImpulseIntegrator::LzbImpulseIntegrator(LzbOptions options)
    : ImpulseStepIntegrator(std::move(options)) {}

void LzbImpulseIntegrator::take_steps(const Input& input, ImpactObserver* observer,
                                      ImpactResult& result) {
  prepare(input.diagonal, input.u_minus, input.laws);
  friction_.prepare(input);
  const LawConstants* law = input.laws.data();
  detail::with_columns(input.H, options().dense_up_to, dense_, [&](const auto& H) {
    if (friction_.on())
      step<true>(H, law, observer, result);
    else
      step<false>(H, law, observer, result);
  });
}

void LzbImpulseIntegrator::prepare(const Eigen::VectorXd& diagonal, const Eigen::VectorXd& u_minus,
                                   const LawTable& laws) {
  const std::size_t m = laws.size();
  Contacts& c = contacts_;
  auto reset = [m](auto& buffer, auto value) { buffer.assign(m, value); };
  reset(c.tolerance_u, 0.0);
  reset(c.tolerance_energy, 0.0);
  if (c.flag_capacity < m) {  // a bool array: no aliasing with the doubles in the hot loop
    c.in_impact = std::make_unique<bool[]>(m);
    c.flag_capacity = m;
  }
  for (std::size_t j = 0; j < m; ++j) {
    c.tolerance_u[j] = options().velocity_tolerance(diagonal(Index(j)));
    c.tolerance_energy[j] = options().energy_tolerance(diagonal(Index(j)));
  }

  c.u.assign(u_minus.data(), u_minus.data() + m);
  c.u_old = c.u;
  for (auto* buffer : {&c.energy, &c.impulse, &c.impulse_carry, &c.step_impulse, &c.force,
                       &c.force_hat, &c.compression_work, &c.work, &c.max_force, &c.time_of_max})
    reset(*buffer, 0.0);
  std::fill_n(c.in_impact.get(), m, false);
  c.active.assign(m, 0);
  c.merge_buffer.assign(m, 0);
  initially_active_ = 0;
  for (std::size_t j = 0; j < m; ++j)
    if (c.u[j] < -c.tolerance_u[j]) {
      c.in_impact[j] = true;
      c.active[initially_active_++] = Index(j);
    }
}

void LzbImpulseIntegrator::notify(ImpactObserver* observer, std::int64_t step, double time,
                                  double principal) {
  const auto value_of = [this](Index j, double& u, double& energy, double& force, double& impulse) {
    u = contacts_.u[j];
    energy = contacts_.energy[j];
    force = contacts_.force[j];
    impulse = contacts_.impulse[j];
  };
  if (friction_.on())
    sampler().observe(*observer, step, time, principal, value_of,
                      [this](Index row) { return friction_.tangential_impulse(row); });
  else
    sampler().observe(*observer, step, time, principal, value_of);
}

namespace {

// The stages of one impulse step (docs/model.md, section 5), on raw pointers to the per-contact
// arrays: local pointers keep the hot loop free of reloads through the vectors' members, and
// each stage is inlined into the step loop.
struct StepArrays {
  const LawConstants* law;
  const double *tolerance_u, *tolerance_energy;
  double *u, *u_old, *energy, *impulse, *impulse_carry, *step_impulse, *force, *force_hat;
  double *compression_work, *work, *max_force, *time_of_max;
  bool* in_impact;
  Index* active;  // capacity m: a contact is listed at most once
  Index* merge_buffer;
  std::size_t active_count;
};

// 1. states. A contact takes part while E_j > tol_E_j or u_j < -tol_u_j: below both it is out
//    (its energy, below what the steps resolve, dropped) until a neighbour pushes it into
//    compression again; the impact ends when no contact takes part. The force-like base is
//    E_j in state 2 and, in state 1 (compression without energy), the energy it would have as
//    primary, |u_j| delta_p. Leaving contacts are dropped in place, so the list stays in index
//    order.
[[gnu::always_inline]] inline void select_participants(StepArrays& a, double delta_p) {
  std::size_t kept = 0;
  for (std::size_t k = 0; k < a.active_count; ++k) {
    const Index j = a.active[k];
    const bool approaching = a.u[j] < -a.tolerance_u[j];
    if (a.energy[j] > a.tolerance_energy[j] || (a.energy[j] > 0.0 && approaching)) {
      a.force_hat[j] = a.energy[j];
    } else if (approaching) {  // here E_j = 0
      a.force_hat[j] = -a.u[j] * delta_p;
    } else {  // state 0
      a.energy[j] = 0.0;
      a.in_impact[j] = false;
      a.force[j] = 0.0;
      a.step_impulse[j] = 0.0;
      continue;
    }
    a.active[kept++] = j;
  }
  a.active_count = kept;
}

// F = c K^(1/(1+eta)) E^(eta/(1+eta)), in a loop of its own so the power calls pipeline; the
// primary contact has the largest force, ties to the lowest index
[[gnu::always_inline]] inline Index find_primary(StepArrays& a) {
  for (std::size_t k = 0; k < a.active_count; ++k) {
    const Index j = a.active[k];
    a.force_hat[j] = a.law[j].coefficient * power_of(a.force_hat[j], a.law[j].power);
  }
  Index primary = -1;
  double primary_force = 0.0;
  for (std::size_t k = 0; k < a.active_count; ++k) {
    const Index j = a.active[k];
    if (a.force_hat[j] > primary_force || (a.force_hat[j] == primary_force && j < primary)) {
      primary = j;
      primary_force = a.force_hat[j];
    }
  }
  return primary;
}

// 2. distributing law: dP_j / dP_pi = F_j / F_pi
[[gnu::always_inline]] inline void distribute(StepArrays& a, Index primary, double delta_p,
                                              double time) {
  const double primary_force = a.force_hat[primary];
  const double impulse_per_force = delta_p / primary_force;
  for (std::size_t k = 0; k < a.active_count; ++k) {
    const Index j = a.active[k];
    double f = a.force_hat[j];
    double dp;
    if (j == primary) {
      dp = delta_p;
    } else if (a.energy[j] > 0.0) {
      dp = f * impulse_per_force;
    } else {  // entering compression: F_j from E_j = |u_j| dP_j, solved for dP_j
      dp = delta_p * power_of(f / primary_force, a.law[j].one_plus_exponent);
      f = dp / impulse_per_force;
    }
    a.step_impulse[j] = dp;
    a.force[j] = f;
    if (f > a.max_force[j]) {
      a.max_force[j] = f;
      a.time_of_max[j] = time;
    }
    a.u_old[j] = a.u[j];
  }
}

// 3. the step ends where the primary's phase ends, if that is inside it: a lone contact then
//    comes out exact, and the primary never loses energy to the clamp at E = 0
template <class Delassus>
[[gnu::always_inline]] inline void cut_at_phase_end(StepArrays& a, const Delassus& H, Index primary,
                                                    double delta_p) {
  double du = 0.0;  // H is symmetric: column pi is row pi
  H.for_each_in_column(primary, [&](Index i, double h_ij) { du += h_ij * a.step_impulse[i]; });
  const LawConstants& law = a.law[primary];
  const double e = law.restitution;
  const bool in_expansion_mono = law.mono_stiffness;
  const double release_level =
      in_expansion_mono
          ? (1.0 - e * e) * (a.u[primary] < 0.0 ? a.energy[primary] : a.compression_work[primary])
          : 0.0;
  const double share =
      detail::phase_end({.u = a.u[primary],
                         .du = du,
                         .energy = a.energy[primary],
                         .delta_p = delta_p,
                         .expansion_rate = in_expansion_mono ? 1.0 : law.inverse_e2,
                         .release_level = release_level,
                         .drops_at_turn = !in_expansion_mono && e == 0.0});
  if (share < 1.0)
    for (std::size_t k = 0; k < a.active_count; ++k) a.step_impulse[a.active[k]] *= share;
}

// 4. velocities u += H dP; a contact pushed into compression joins the impact (appended)
template <class Delassus>
[[gnu::always_inline]] inline void propagate(StepArrays& a, const Delassus& H,
                                             std::size_t stepping) {
  for (std::size_t k = 0; k < stepping; ++k) {
    const Index j = a.active[k];
    const double dp = a.step_impulse[j];
    H.for_each_in_column(j, [&](Index i, double h_ij) {
      a.u[i] += h_ij * dp;
      if (!a.in_impact[i] && a.u[i] < -a.tolerance_u[i]) {
        a.in_impact[i] = true;
        a.active[a.active_count++] = i;
      }
    });
  }
}

// 5. energies, with the trapezoidal work of the step; returns the primary's energy at the
//    step's end before any clamp or reset, for the step's duration
[[gnu::always_inline]] inline double update_energies(StepArrays& a, Index primary,
                                                     std::size_t stepping) {
  double primary_energy_end = 0.0;
  for (std::size_t k = 0; k < stepping; ++k) {
    const Index j = a.active[k];
    const LawConstants& law = a.law[j];
    const double dp = a.step_impulse[j];
    const double mean_u = 0.5 * (a.u_old[j] + a.u[j]);
    a.work[j] -= mean_u * dp;
    // compensated (Kahan) sum: a billion steps of delta_p keep P to round-off
    const double added = dp - a.impulse_carry[j];
    const double sum = a.impulse[j] + added;
    a.impulse_carry[j] = (sum - a.impulse[j]) - added;
    a.impulse[j] = sum;
    double e_j = a.energy[j];
    if (law.mono_stiffness) {
      if (a.u_old[j] < 0.0 && a.u[j] >= 0.0) {
        // the compression work is the energy where u crosses 0 inside the step
        const double share = -a.u_old[j] / (a.u[j] - a.u_old[j]);
        a.compression_work[j] = e_j - 0.5 * a.u_old[j] * share * dp;
      }
      e_j -= mean_u * dp;
      if (j == primary) primary_energy_end = e_j;
      const double e = law.restitution;
      if (a.u[j] >= 0.0 && e_j <= (1.0 - e * e) * a.compression_work[j]) e_j = 0.0;
    } else if (mean_u < 0.0) {
      e_j -= mean_u * dp;
    } else {  // e = 0 drops the energy at once, as if it fell to -infinity
      e_j = law.restitution > 0.0 ? e_j - mean_u * dp * law.inverse_e2 : -INFINITY;
    }
    if (j == primary && !law.mono_stiffness) primary_energy_end = e_j;
    a.energy[j] = std::max(e_j, 0.0);
  }
  return primary_energy_end;
}

// the contacts that joined are merged into the list in index order, so the per-contact arrays
// are read in address order: neighbouring contacts have nearby indices and share cache lines
// (a 56 x 56 packing's impact takes a third less time than in join order)
[[gnu::always_inline]] inline void merge_joined(StepArrays& a, std::size_t stepping) {
  if (a.active_count == stepping) return;
  std::sort(a.active + stepping, a.active + a.active_count);
  std::merge(a.active, a.active + stepping, a.active + stepping, a.active + a.active_count,
             a.merge_buffer);
  std::copy(a.merge_buffer, a.merge_buffer + a.active_count, a.active);
}

// 3b. the frictional contacts' tangential impulses (ImpulseStepFriction); a contact whose u
//     they push into compression joins the impact
void step_friction(ImpulseStepFriction& friction, StepArrays& a, std::size_t stepping) {
  friction.step({a.active, stepping}, a.step_impulse, a.u);
  for (Index i : friction.pushed())
    if (!a.in_impact[i] && a.u[i] < -a.tolerance_u[i]) {
      a.in_impact[i] = true;
      a.active[a.active_count++] = i;
    }
}

}  // namespace

template <bool Frictional, class Delassus>
void LzbImpulseIntegrator::step(const Delassus& H, const LawConstants* law,
                                ImpactObserver* observer, ImpactResult& result) {
  Contacts& c = contacts_;
  StepArrays a{law,
               c.tolerance_u.data(),
               c.tolerance_energy.data(),
               c.u.data(),
               c.u_old.data(),
               c.energy.data(),
               c.impulse.data(),
               c.impulse_carry.data(),
               c.step_impulse.data(),
               c.force.data(),
               c.force_hat.data(),
               c.compression_work.data(),
               c.work.data(),
               c.max_force.data(),
               c.time_of_max.data(),
               c.in_impact.get(),
               c.active.data(),
               c.merge_buffer.data(),
               initially_active_};
  const double delta_p = options().delta_p;
  std::int64_t step = 0;
  double time = 0.0, principal = 0.0;
  if (observer) notify(observer, step, time, principal);
  ObserverSchedule schedule(observer, options().sample_every);
  while (true) {
    select_participants(a, delta_p);
    if (a.active_count == 0) break;
    const Index primary = find_primary(a);
    if (step >= options().max_steps) {
      result.status = ImpactStatus::step_limit;
      result.message =
          "the impact did not end within max_steps = " + std::to_string(options().max_steps) +
          " impulse steps; raise max_steps or delta_p";
      break;
    }
    const double primary_force = a.force_hat[primary];
    distribute(a, primary, delta_p, time);
    cut_at_phase_end(a, H, primary, delta_p);
    const std::size_t stepping = a.active_count;
    result.contact_steps += std::int64_t(stepping);
    if constexpr (Frictional) step_friction(friction_, a, stepping);
    propagate(a, H, stepping);
    const double primary_energy_start = a.energy[primary];
    const double primary_energy_end = update_energies(a, primary, stepping);
    merge_joined(a, stepping);
    time += detail::step_duration(a.step_impulse[primary], primary_energy_start, primary_energy_end,
                                  primary_force, law[primary].coefficient, law[primary].power);
    principal += a.step_impulse[primary];
    ++step;
    if (schedule.due(step)) {
      const ObserverSchedule::Due due = schedule.take(step);
      if (due.sample) notify(observer, step, time, principal);
      if (due.progress)
        observer->progressed({.step = step, .time = time, .principal_impulse = principal});
    }
  }
  if (observer) notify(observer, step, time, principal);

  const Index m = Index(c.u.size());
  result.impulse = Eigen::Map<const Eigen::VectorXd>(a.impulse, m);
  result.max_force = Eigen::Map<const Eigen::VectorXd>(a.max_force, m);
  result.time_of_max_force = Eigen::Map<const Eigen::VectorXd>(a.time_of_max, m);
  result.work = Eigen::Map<const Eigen::VectorXd>(a.work, m);
  result.stored_energy = Eigen::Map<const Eigen::VectorXd>(a.energy, m);
  result.steps = step;
  result.duration = time;
  friction_.finish(result);
}

}  // namespace mimpact::numerics
