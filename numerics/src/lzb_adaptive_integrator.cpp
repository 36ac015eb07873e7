#include "mimpact/numerics/lzb_adaptive_integrator.hpp"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <span>
#include <string>

#include "lzb_adaptive_impact.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/numerics/dense_output.hpp"
#include "mimpact/numerics/event_scan.hpp"
#include "mimpact/numerics/root_bracketing.hpp"

namespace mimpact::numerics {

using Eigen::Index;
using namespace adaptive_lzb;  // the impact's phases, switches and constants

void adaptive_lzb::Impact::prepare(const Eigen::VectorXd& diagonal, const Eigen::VectorXd& u_minus,
                                   const LawTable& laws, const LzbAdaptiveOptions& options) {
  const std::size_t m = laws.size();
  const double fastest = -u_minus.minCoeff();
  velocity_tolerance_ = options.tolerance * fastest;
  sample_interval_ = options.sample_interval;
  law_.reset(m);
  local_tolerance_ = kLocalErrorShare * options.tolerance;
  for (std::size_t j = 0; j < m; ++j) {
    const LawConstants& law = laws[j];
    const double e2 = law.restitution * law.restitution;
    const bool mono = law.mono_stiffness;
    law_.stiffness[j] = law.stiffness;
    law_.exponent[j] = law.exponent;
    // expansion: d delta/dt = -u / e^2 (bi-stiffness) or -u (mono-stiffness)
    law_.expansion_rate[j] = mono || e2 == 0.0 ? 1.0 : law.inverse_e2;
    // released at delta_c (1 - e^2)^(1/(1+eta)) (mono-stiffness) or at 0 (bi-stiffness)
    law_.release_factor[j] = mono ? std::pow(1.0 - e2, 1.0 / law.one_plus_exponent) : 0.0;
    law_.gives_nothing_back[j] = law.restitution == 0.0;
    // the natural scales of contact j: the impulse that stops V, the indentation that stores
    // the energy V^2 / (2 H_jj)
    const double h = diagonal(Index(j));
    law_.self_mobility[j] = h;
    law_.impulse_scale[j] = fastest / h;
    law_.delta_scale[j] =
        std::pow((1.0 + law.exponent) * fastest * fastest / (2.0 * h * law.stiffness),
                 1.0 / (1.0 + law.exponent));
    law_.energy_tolerance[j] = velocity_tolerance_ * velocity_tolerance_ / (2.0 * h);
  }
  contact_.reset(u_minus);
  for (std::size_t j = 0; j < m; ++j)
    if (contact_.velocity[j] < -velocity_tolerance_) contact_.phase[j] = Phase::compression;
  segment_.members.clear();
  within_.pending.clear();
  within_.continuous_laws = m > 0;
  for (std::size_t j = 0; j < m; ++j)
    within_.continuous_laws =
        within_.continuous_laws &&
        (laws[j].restitution == 1.0 || (!laws[j].mono_stiffness && laws[j].restitution > 0.0));
  within_.on = false;
  within_.enter = std::size_t(options.within_steps_from);
  within_.leave = within_.enter / 2;
  steps_ = contact_steps_ = 0;
  segment_start_ = last_sample_ = closed_impulse_sum_ = 0.0;
}

// The members of the segment that starts now: the contacts holding energy, then the open
// contacts their forces reach through H. The ODE state starts at [delta / scale, 0].
void adaptive_lzb::Impact::begin_segment() {
  if (within_.continuous_laws) {
    std::size_t core = 0;
    auto count = [&](Index j) { core += takes_part(j); };
    if (segment_.members.empty())
      for (Index j = 0; j < Index(contact_.phase.size()); ++j) count(j);
    for (Index j : segment_.members) count(j);
    core += within_.pending.size();
    within_.on = core >= (within_.on ? within_.leave : within_.enter);
  }
  if (within_.on) {
    begin_within_steps_segment();
    return;
  }
  for (Index j : segment_.members) contact_.member_of[j] = -1;
  std::vector<Index>& previous = segment_.previous_members;
  previous.swap(segment_.members);
  segment_.members.clear();
  previous.insert(previous.end(), within_.pending.begin(), within_.pending.end());
  within_.pending.clear();
  // the active contacts were members already (a contact becomes active only by a switch at a
  // member), so the new active set is found among the previous members, in their order
  for (Index j : previous)
    if (contact_.phase[j] != Phase::open) {
      contact_.member_of[j] = int(segment_.members.size());
      segment_.members.push_back(j);
    }
  if (previous.empty())  // the first segment
    for (Index j = 0; j < Index(contact_.phase.size()); ++j)
      if (contact_.phase[j] != Phase::open) {
        contact_.member_of[j] = int(segment_.members.size());
        segment_.members.push_back(j);
      }
  segment_.active = segment_.members.size();
  const int* start = H_->outerIndexPtr();
  const int* row = H_->innerIndexPtr();
  for (std::size_t a = 0; a < segment_.active; ++a)
    for (int k = start[segment_.members[a]]; k < start[segment_.members[a] + 1]; ++k)
      if (contact_.member_of[row[k]] < 0) {
        contact_.member_of[row[k]] = int(segment_.members.size());
        segment_.members.push_back(row[k]);
      }
  size_segment();
}

// The ODE state [delta / scale, 0] of the members that carry one, and the buffers.
void adaptive_lzb::Impact::size_segment() {
  segment_.y.assign(2 * segment_.active, 0.0);
  segment_.y_at.assign(2 * segment_.active, 0.0);
  segment_.rate.resize(segment_.active);
  for (std::size_t a = 0; a < segment_.active; ++a) {
    const Index j = segment_.members[a];
    segment_.y[a] = contact_.delta[j] / law_.delta_scale[j];
    segment_.rate[a] = contact_.phase[j] == Phase::expansion ? law_.expansion_rate[j] : 1.0;
  }
  segment_.rhs_velocity.resize(segment_.members.size());
  segment_.velocity_at.resize(segment_.members.size());
  segment_.accounted_impulse.assign(segment_.active, 0.0);
  segment_.accounted_velocity.resize(segment_.active);
  for (std::size_t a = 0; a < segment_.active; ++a)
    segment_.accounted_velocity[a] = contact_.velocity[segment_.members[a]];
}

// The contacts' work since the last accounting point, by the trapezoidal rule on u: per contact
// an approximation of the integral of -u_j dP_j, summed over them exact, since u is linear in P
// (the kinetic energy lost to round-off, docs/model.md section 12; docs/design/adaptive_lzb.md).
void adaptive_lzb::Impact::account_work(const State& y) {
  member_velocities(y, segment_.velocity_at);
  for (std::size_t a = 0; a < segment_.active; ++a) {
    const Index j = segment_.members[a];
    const double impulse = y[segment_.active + a] * law_.impulse_scale[j];
    contact_.work[j] -= 0.5 * (segment_.accounted_velocity[a] + segment_.velocity_at[a]) *
                        (impulse - segment_.accounted_impulse[a]);
    segment_.accounted_velocity[a] = segment_.velocity_at[a];
    segment_.accounted_impulse[a] = impulse;
  }
}

void adaptive_lzb::Impact::derivative(const State& y, State& dydt) {
  member_velocities(y, segment_.rhs_velocity);
  for (std::size_t a = 0; a < segment_.active; ++a) {
    const Index j = segment_.members[a];
    dydt[a] = -segment_.rhs_velocity[a] * segment_.rate[a] / law_.delta_scale[j];
    dydt[segment_.active + a] = force(j, delta_of(a, y)) / law_.impulse_scale[j];
  }
}

// Writes the members' state at the end of the segment (state y) into the per-contact arrays.
void adaptive_lzb::Impact::end_segment(const State& y) {
  member_velocities(y, segment_.velocity_at);
  for (std::size_t p = 0; p < segment_.members.size(); ++p)
    contact_.velocity[segment_.members[p]] = segment_.velocity_at[p];
  const int* start = H_->outerIndexPtr();
  const int* row = H_->innerIndexPtr();
  const double* value = H_->valuePtr();
  for (std::size_t a = 0; a < segment_.active; ++a) {
    const Index j = segment_.members[a];
    contact_.delta[j] = delta_of(a, y);
    const double increment = y[segment_.active + a] * law_.impulse_scale[j];
    contact_.impulse[j] += increment;
    closed_impulse_sum_ += increment;
    if (!within_.on) continue;
    // the phases a segment that locates its switches starts from
    const double u = contact_.velocity[j];
    contact_.phase[j] = contact_.delta[j] > 0.0 ? (u < 0.0 ? Phase::compression : Phase::expansion)
                        : u < -velocity_tolerance_ ? Phase::compression
                                                   : Phase::open;
    // an outer ring's contact that loaded within the last step moved contacts beyond the members
    if (within_.ring[a] == 2 && increment != 0.0)
      for (int k = start[j]; k < start[j + 1]; ++k)
        if (const Index other = row[k]; contact_.member_of[other] < 0) {
          contact_.velocity[other] += value[k] * increment;
          if (contact_.velocity[other] < -velocity_tolerance_ &&
              contact_.phase[other] == Phase::open) {
            contact_.phase[other] = Phase::compression;  // joining
            within_.pending.push_back(other);
          }
        }
  }
}

void adaptive_lzb::Impact::apply(const std::vector<Crossing>& crossings, double t) {
  for (const Crossing& crossing : crossings) {
    const Index j = segment_.members[std::size_t(crossing.index)];
    switch (crossing.kind) {
      case join:
        contact_.phase[j] = Phase::compression;
        contact_.delta[j] = 0.0;
        break;
      case compression_end:
        if (const double f = force(j, contact_.delta[j]); f > contact_.max_force[j]) {
          contact_.max_force[j] = f;
          contact_.time_of_max[j] = t;
        }
        contact_.phase[j] = law_.gives_nothing_back[j] ? Phase::open : Phase::expansion;
        if (law_.gives_nothing_back[j]) contact_.delta[j] = 0.0;
        contact_.release_level[j] = law_.release_factor[j] * contact_.delta[j];
        break;
      case reload:
        contact_.phase[j] = Phase::compression;
        break;
      default:  // release
        contact_.phase[j] = Phase::open;
        contact_.delta[j] = 0.0;
        break;
    }
  }
}

// The impact's end: no contact approaches faster than tolerance * V and none holds more
// than its energy tolerance (the open ones are known to approach slower: they would have
// joined).
bool adaptive_lzb::Impact::settled(const State& y) {
  member_velocities(y, segment_.velocity_at);
  for (std::size_t a = 0; a < segment_.active; ++a) {
    const Index j = segment_.members[a];
    if (segment_.velocity_at[a] < -velocity_tolerance_ ||
        energy(j, delta_of(a, y)) > law_.energy_tolerance[j])
      return false;
  }
  return true;
}

void adaptive_lzb::Impact::notify(double t, const State* y, ImpactObserver& observer) {
  if (y) member_velocities(*y, segment_.velocity_at);
  double impulse_sum = closed_impulse_sum_;
  if (y)
    for (std::size_t a = 0; a < segment_.active; ++a)
      impulse_sum += (*y)[segment_.active + a] * law_.impulse_scale[segment_.members[a]];
  sampler_->observe(
      observer, steps_, t, impulse_sum,
      [&](Index j, double& u, double& energy_now, double& force_now, double& impulse) {
        const int p = y ? contact_.member_of[j] : -1;
        const bool active = p >= 0 && std::size_t(p) < segment_.active;
        const double delta = active ? delta_of(std::size_t(p), *y) : contact_.delta[j];
        u = p >= 0 ? segment_.velocity_at[std::size_t(p)] : contact_.velocity[j];
        energy_now = energy(j, delta);
        force_now = force(j, delta);
        impulse = contact_.impulse[j] +
                  (active ? (*y)[segment_.active + std::size_t(p)] * law_.impulse_scale[j] : 0.0);
      });
}

// The samples of the observer that fall in the part of the current step up to t.
void adaptive_lzb::Impact::sample_until(double t, ImpactObserver& observer) {
  if (sample_interval_ <= 0.0) return;
  for (double next = last_sample_ + sample_interval_; next <= t;
       next = last_sample_ + sample_interval_) {
    ode_.state_at(next, segment_.y_at);
    notify(next, &segment_.y_at, observer);
    last_sample_ = next;
  }
}

void adaptive_lzb::Impact::finish(double t, ImpactResult& result) {
  const std::size_t m = contact_.phase.size();
  result.impulse = Eigen::Map<const Eigen::VectorXd>(contact_.impulse.data(), Index(m));
  result.work = Eigen::Map<const Eigen::VectorXd>(contact_.work.data(), Index(m));
  result.stored_energy = Eigen::VectorXd::Zero(Index(m));
  for (std::size_t j = 0; j < m; ++j) {
    if (contact_.phase[j] == Phase::open) continue;
    result.stored_energy(Index(j)) = energy(Index(j), contact_.delta[j]);
    if (const double f = force(Index(j), contact_.delta[j]); f > contact_.max_force[j]) {
      contact_.max_force[j] = f;  // still in compression at the end
      contact_.time_of_max[j] = t;
    }
  }
  result.max_force = Eigen::Map<const Eigen::VectorXd>(contact_.max_force.data(), Index(m));
  result.time_of_max_force =
      Eigen::Map<const Eigen::VectorXd>(contact_.time_of_max.data(), Index(m));
  result.steps = steps_;
  result.contact_steps = contact_steps_;
  result.duration = t;
}

void adaptive_lzb::Impact::run(const ImpactIntegrator::Input& input,
                               const LzbAdaptiveOptions& options, ImpactSampler& sampler,
                               ImpactObserver* observer, ImpactResult& result) {
  const Eigen::VectorXd& u_minus = input.u_minus;
  H_ = &input.H;
  sampler_ = &sampler;
  prepare(input.diagonal, u_minus, input.laws, options);
  begin_segment();
  // the first step: a small share of the time the fastest contact takes to stop
  double first_step = 1.0;
  for (std::size_t a = 0; a < segment_.active; ++a)
    if (u_minus(segment_.members[a]) < 0.0)
      first_step = std::min(first_step,
                            law_.delta_scale[segment_.members[a]] / -u_minus(segment_.members[a]));
  ode_.restart(segment_.y, 0.0, 1e-3 * first_step);
  if (observer) notify(0.0, &segment_.y, *observer);
  auto rhs = [this](const State& y, State& dydt, double) { derivative(y, dydt); };

  std::int64_t restarts = 0;
  double t = 0.0;
  while (true) {
    if (steps_ + restarts >= options.max_steps) {
      account_work(ode_.state());
      end_segment(ode_.state());
      finish(ode_.time(), result);
      result.status = ImpactStatus::step_limit;
      result.message =
          "the impact did not end within max_steps = " + std::to_string(options.max_steps) +
          " steps and restarts";
      if (observer) notify(result.duration, nullptr, *observer);
      return;
    }
    const double step_start = ode_.time();
    ode_.step(rhs);
    ++steps_;
    contact_steps_ += std::int64_t(segment_.active);
    const std::vector<Crossing> found = scan_events(
        {.start = step_start, .end = ode_.time(), .samples = kSamplesPerStep + 1}, segment_.before,
        segment_.after, [this](double time, Watched& v) { watch(time, v); },
        [this](double t0, double t1, const Watched& b, const Watched& a, std::vector<Crossing>& f) {
          locate(t0, t1, b, a, f);
        });
    if (found.empty()) {
      t = ode_.time();
      const bool changed = within_.on && settle_turns(step_start, t);
      const State& y = changed ? within_.y_settled : ode_.state();
      account_work(y);
      if (observer) sample_until(t, *observer);
      const bool grow = within_.on && outgrown(y);
      if (!grow && settled(y)) {
        end_segment(y);
        break;
      }
      if (changed || grow) {
        // a state set back, or members to add: the same step goes on from here
        end_segment(y);
        begin_segment();
        if (segment_.active == 0) break;
        ode_.restart(segment_.y, t, ode_.next_step());
        segment_start_ = t;
      }
      continue;
    }
    t = found.front().time;
    if (observer) sample_until(t, *observer);
    ode_.state_at(t, segment_.y_at);
    account_work(segment_.y_at);
    end_segment(segment_.y_at);
    apply(found, t);
    const double last_step = ode_.last_step();
    begin_segment();
    if (segment_.active == 0) break;
    ode_.restart(segment_.y, t, last_step);
    segment_start_ = t;
    ++restarts;
  }
  finish(t, result);
  if (observer) notify(t, nullptr, *observer);
}

LzbAdaptiveIntegrator::LzbAdaptiveIntegrator(LzbAdaptiveOptions options)
    : ImpactIntegrator(options.sampled_contacts), options_(std::move(options)) {
  validate(options_, "adaptive LZB options");
}

LzbAdaptiveIntegrator::~LzbAdaptiveIntegrator() = default;
LzbAdaptiveIntegrator::LzbAdaptiveIntegrator(LzbAdaptiveIntegrator&&) noexcept = default;
LzbAdaptiveIntegrator& LzbAdaptiveIntegrator::operator=(LzbAdaptiveIntegrator&&) noexcept = default;

void LzbAdaptiveIntegrator::set_tolerance(double tolerance) {
  LzbAdaptiveOptions changed = options_;
  changed.tolerance = tolerance;
  validate(changed, "adaptive LZB options");
  options_ = std::move(changed);
  impact_.reset();
}

Eigen::VectorXd LzbAdaptiveIntegrator::velocity_resolution(const Eigen::VectorXd& diagonal,
                                                           const Eigen::VectorXd& u_minus) const {
  return Eigen::VectorXd::Constant(diagonal.size(), options_.tolerance * (-u_minus.minCoeff()));
}

void LzbAdaptiveIntegrator::run(const Input& input, ImpactObserver* observer,
                                ImpactResult& result) {
  if (!impact_) impact_ = std::make_unique<Impact>(options_.tolerance);
  impact_->run(input, options_, sampler(), observer, result);
}

}  // namespace mimpact::numerics
