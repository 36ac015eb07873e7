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
  auto reset = [m](auto& buffer, auto value) { buffer.assign(m, value); };
  reset(stiffness_, 0.0);
  reset(exponent_, 0.0);
  reset(expansion_rate_, 0.0);
  reset(release_factor_, 0.0);
  reset(delta_scale_, 0.0);
  reset(impulse_scale_, 0.0);
  reset(energy_tolerance_, 0.0);
  reset(self_mobility_, 0.0);
  local_tolerance_ = kLocalErrorShare * options.tolerance;
  reset(gives_nothing_back_, false);
  for (std::size_t j = 0; j < m; ++j) {
    const LawConstants& law = laws[j];
    const double e2 = law.restitution * law.restitution;
    const bool mono = law.mono_stiffness;
    stiffness_[j] = law.stiffness;
    exponent_[j] = law.exponent;
    // expansion: d delta/dt = -u / e^2 (bi-stiffness) or -u (mono-stiffness)
    expansion_rate_[j] = mono || e2 == 0.0 ? 1.0 : law.inverse_e2;
    // released at delta_c (1 - e^2)^(1/(1+eta)) (mono-stiffness) or at 0 (bi-stiffness)
    release_factor_[j] = mono ? std::pow(1.0 - e2, 1.0 / law.one_plus_exponent) : 0.0;
    gives_nothing_back_[j] = law.restitution == 0.0;
    // the natural scales of contact j: the impulse that stops V, the indentation that stores
    // the energy V^2 / (2 H_jj)
    const double h = diagonal(Index(j));
    self_mobility_[j] = h;
    impulse_scale_[j] = fastest / h;
    delta_scale_[j] = std::pow((1.0 + law.exponent) * fastest * fastest / (2.0 * h * law.stiffness),
                               1.0 / (1.0 + law.exponent));
    energy_tolerance_[j] = velocity_tolerance_ * velocity_tolerance_ / (2.0 * h);
  }
  reset(phase_, Phase::open);
  reset(delta_, 0.0);
  reset(impulse_, 0.0);
  reset(release_level_, 0.0);
  reset(max_force_, 0.0);
  reset(time_of_max_, 0.0);
  reset(work_, 0.0);
  reset(member_of_, -1);
  velocity_.assign(u_minus.data(), u_minus.data() + m);
  for (std::size_t j = 0; j < m; ++j)
    if (velocity_[j] < -velocity_tolerance_) phase_[j] = Phase::compression;
  members_.clear();
  pending_.clear();
  continuous_laws_ = m > 0;
  for (std::size_t j = 0; j < m; ++j)
    continuous_laws_ = continuous_laws_ && (laws[j].restitution == 1.0 ||
                                            (!laws[j].mono_stiffness && laws[j].restitution > 0.0));
  within_steps_ = false;
  enter_within_steps_ = std::size_t(options.within_steps_from);
  leave_within_steps_ = enter_within_steps_ / 2;
  steps_ = contact_steps_ = 0;
  segment_start_ = last_sample_ = closed_impulse_sum_ = 0.0;
}

// The members of the segment that starts now: the contacts holding energy, then the open
// contacts their forces reach through H. The ODE state starts at [delta / scale, 0].
void adaptive_lzb::Impact::begin_segment() {
  if (continuous_laws_) {
    std::size_t core = 0;
    auto count = [&](Index j) { core += takes_part(j); };
    if (members_.empty())
      for (Index j = 0; j < Index(phase_.size()); ++j) count(j);
    for (Index j : members_) count(j);
    core += pending_.size();
    within_steps_ = core >= (within_steps_ ? leave_within_steps_ : enter_within_steps_);
  }
  if (within_steps_) {
    begin_within_steps_segment();
    return;
  }
  for (Index j : members_) member_of_[j] = -1;
  std::vector<Index>& previous = previous_members_;
  previous.swap(members_);
  members_.clear();
  previous.insert(previous.end(), pending_.begin(), pending_.end());
  pending_.clear();
  // the active contacts were members already (a contact becomes active only by a switch at a
  // member), so the new active set is found among the previous members, in their order
  for (Index j : previous)
    if (phase_[j] != Phase::open) {
      member_of_[j] = int(members_.size());
      members_.push_back(j);
    }
  if (previous.empty())  // the first segment
    for (Index j = 0; j < Index(phase_.size()); ++j)
      if (phase_[j] != Phase::open) {
        member_of_[j] = int(members_.size());
        members_.push_back(j);
      }
  active_ = members_.size();
  const int* start = H_->outerIndexPtr();
  const int* row = H_->innerIndexPtr();
  for (std::size_t a = 0; a < active_; ++a)
    for (int k = start[members_[a]]; k < start[members_[a] + 1]; ++k)
      if (member_of_[row[k]] < 0) {
        member_of_[row[k]] = int(members_.size());
        members_.push_back(row[k]);
      }
  size_segment();
}

// The ODE state [delta / scale, 0] of the members that carry one, and the buffers.
void adaptive_lzb::Impact::size_segment() {
  y_.assign(2 * active_, 0.0);
  y_at_.assign(2 * active_, 0.0);
  rate_.resize(active_);
  for (std::size_t a = 0; a < active_; ++a) {
    const Index j = members_[a];
    y_[a] = delta_[j] / delta_scale_[j];
    rate_[a] = phase_[j] == Phase::expansion ? expansion_rate_[j] : 1.0;
  }
  rhs_velocity_.resize(members_.size());
  velocity_at_.resize(members_.size());
  accounted_impulse_.assign(active_, 0.0);
  accounted_velocity_.resize(active_);
  for (std::size_t a = 0; a < active_; ++a) accounted_velocity_[a] = velocity_[members_[a]];
}

// The contacts' work since the last accounting point, by the trapezoidal rule on u: per contact
// an approximation of the integral of -u_j dP_j, summed over them exact, since u is linear in P
// (the kinetic energy lost to round-off, docs/model.md section 12; docs/design/adaptive_lzb.md).
void adaptive_lzb::Impact::account_work(const State& y) {
  member_velocities(y, velocity_at_);
  for (std::size_t a = 0; a < active_; ++a) {
    const Index j = members_[a];
    const double impulse = y[active_ + a] * impulse_scale_[j];
    work_[j] -=
        0.5 * (accounted_velocity_[a] + velocity_at_[a]) * (impulse - accounted_impulse_[a]);
    accounted_velocity_[a] = velocity_at_[a];
    accounted_impulse_[a] = impulse;
  }
}

void adaptive_lzb::Impact::derivative(const State& y, State& dydt) {
  member_velocities(y, rhs_velocity_);
  for (std::size_t a = 0; a < active_; ++a) {
    const Index j = members_[a];
    dydt[a] = -rhs_velocity_[a] * rate_[a] / delta_scale_[j];
    dydt[active_ + a] = force(j, delta_of(a, y)) / impulse_scale_[j];
  }
}

// Writes the members' state at the end of the segment (state y) into the per-contact arrays.
void adaptive_lzb::Impact::end_segment(const State& y) {
  member_velocities(y, velocity_at_);
  for (std::size_t p = 0; p < members_.size(); ++p) velocity_[members_[p]] = velocity_at_[p];
  const int* start = H_->outerIndexPtr();
  const int* row = H_->innerIndexPtr();
  const double* value = H_->valuePtr();
  for (std::size_t a = 0; a < active_; ++a) {
    const Index j = members_[a];
    delta_[j] = delta_of(a, y);
    const double increment = y[active_ + a] * impulse_scale_[j];
    impulse_[j] += increment;
    closed_impulse_sum_ += increment;
    if (!within_steps_) continue;
    // the phases a segment that locates its switches starts from
    const double u = velocity_[j];
    phase_[j] = delta_[j] > 0.0            ? (u < 0.0 ? Phase::compression : Phase::expansion)
                : u < -velocity_tolerance_ ? Phase::compression
                                           : Phase::open;
    // an outer ring's contact that loaded within the last step moved contacts beyond the members
    if (ring_[a] == 2 && increment != 0.0)
      for (int k = start[j]; k < start[j + 1]; ++k)
        if (const Index other = row[k]; member_of_[other] < 0) {
          velocity_[other] += value[k] * increment;
          if (velocity_[other] < -velocity_tolerance_ && phase_[other] == Phase::open) {
            phase_[other] = Phase::compression;  // joining
            pending_.push_back(other);
          }
        }
  }
}

void adaptive_lzb::Impact::apply(const std::vector<Crossing>& crossings, double t) {
  for (const Crossing& crossing : crossings) {
    const Index j = members_[std::size_t(crossing.index)];
    switch (crossing.kind) {
      case join:
        phase_[j] = Phase::compression;
        delta_[j] = 0.0;
        break;
      case compression_end:
        if (const double f = force(j, delta_[j]); f > max_force_[j]) {
          max_force_[j] = f;
          time_of_max_[j] = t;
        }
        phase_[j] = gives_nothing_back_[j] ? Phase::open : Phase::expansion;
        if (gives_nothing_back_[j]) delta_[j] = 0.0;
        release_level_[j] = release_factor_[j] * delta_[j];
        break;
      case reload:
        phase_[j] = Phase::compression;
        break;
      default:  // release
        phase_[j] = Phase::open;
        delta_[j] = 0.0;
        break;
    }
  }
}

// The impact's end: no contact approaches faster than tolerance * V and none holds more
// than its energy tolerance (the open ones are known to approach slower: they would have
// joined).
bool adaptive_lzb::Impact::settled(const State& y) {
  member_velocities(y, velocity_at_);
  for (std::size_t a = 0; a < active_; ++a) {
    const Index j = members_[a];
    if (velocity_at_[a] < -velocity_tolerance_ || energy(j, delta_of(a, y)) > energy_tolerance_[j])
      return false;
  }
  return true;
}

void adaptive_lzb::Impact::notify(double t, const State* y, ImpactObserver& observer) {
  if (y) member_velocities(*y, velocity_at_);
  double impulse_sum = closed_impulse_sum_;
  if (y)
    for (std::size_t a = 0; a < active_; ++a)
      impulse_sum += (*y)[active_ + a] * impulse_scale_[members_[a]];
  sampler_->observe(
      observer, steps_, t, impulse_sum,
      [&](Index j, double& u, double& energy_now, double& force_now, double& impulse) {
        const int p = y ? member_of_[j] : -1;
        const bool active = p >= 0 && std::size_t(p) < active_;
        const double delta = active ? delta_of(std::size_t(p), *y) : delta_[j];
        u = p >= 0 ? velocity_at_[std::size_t(p)] : velocity_[j];
        energy_now = energy(j, delta);
        force_now = force(j, delta);
        impulse = impulse_[j] + (active ? (*y)[active_ + std::size_t(p)] * impulse_scale_[j] : 0.0);
      });
}

// The samples of the observer that fall in the part of the current step up to t.
void adaptive_lzb::Impact::sample_until(double t, ImpactObserver& observer) {
  if (sample_interval_ <= 0.0) return;
  for (double next = last_sample_ + sample_interval_; next <= t;
       next = last_sample_ + sample_interval_) {
    ode_.state_at(next, y_at_);
    notify(next, &y_at_, observer);
    last_sample_ = next;
  }
}

void adaptive_lzb::Impact::finish(double t, ImpactResult& result) {
  const std::size_t m = phase_.size();
  result.impulse = Eigen::Map<const Eigen::VectorXd>(impulse_.data(), Index(m));
  result.work = Eigen::Map<const Eigen::VectorXd>(work_.data(), Index(m));
  result.stored_energy = Eigen::VectorXd::Zero(Index(m));
  for (std::size_t j = 0; j < m; ++j) {
    if (phase_[j] == Phase::open) continue;
    result.stored_energy(Index(j)) = energy(Index(j), delta_[j]);
    if (const double f = force(Index(j), delta_[j]); f > max_force_[j]) {
      max_force_[j] = f;  // still in compression at the end
      time_of_max_[j] = t;
    }
  }
  result.max_force = Eigen::Map<const Eigen::VectorXd>(max_force_.data(), Index(m));
  result.time_of_max_force = Eigen::Map<const Eigen::VectorXd>(time_of_max_.data(), Index(m));
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
  for (std::size_t a = 0; a < active_; ++a)
    if (u_minus(members_[a]) < 0.0)
      first_step = std::min(first_step, delta_scale_[members_[a]] / -u_minus(members_[a]));
  ode_.restart(y_, 0.0, 1e-3 * first_step);
  if (observer) notify(0.0, &y_, *observer);
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
    contact_steps_ += std::int64_t(active_);
    const std::vector<Crossing> found = scan_events(
        {.start = step_start, .end = ode_.time(), .samples = kSamplesPerStep + 1}, before_, after_,
        [this](double time, Watched& v) { watch(time, v); },
        [this](double t0, double t1, const Watched& b, const Watched& a, std::vector<Crossing>& f) {
          locate(t0, t1, b, a, f);
        });
    if (found.empty()) {
      t = ode_.time();
      const bool changed = within_steps_ && settle_turns(step_start, t);
      const State& y = changed ? y_settled_ : ode_.state();
      account_work(y);
      if (observer) sample_until(t, *observer);
      const bool grow = within_steps_ && outgrown(y);
      if (!grow && settled(y)) {
        end_segment(y);
        break;
      }
      if (changed || grow) {
        // a state set back, or members to add: the same step goes on from here
        end_segment(y);
        begin_segment();
        if (active_ == 0) break;
        ode_.restart(y_, t, ode_.next_step());
        segment_start_ = t;
      }
      continue;
    }
    t = found.front().time;
    if (observer) sample_until(t, *observer);
    ode_.state_at(t, y_at_);
    account_work(y_at_);
    end_segment(y_at_);
    apply(found, t);
    const double last_step = ode_.last_step();
    begin_segment();
    if (active_ == 0) break;
    ode_.restart(y_, t, last_step);
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
