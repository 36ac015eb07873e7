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

void adaptive_lzb::Impact::prepare(const ImpactIntegrator::Input& input,
                                   const LzbAdaptiveOptions& options) {
  const Eigen::VectorXd& diagonal = input.diagonal;
  const Eigen::VectorXd& u_minus = input.u_minus;
  const LawTable& laws = input.laws;
  const std::size_t m = laws.size();
  const double fastest = -u_minus.minCoeff();
  shared_.velocity_tolerance = options.tolerance * fastest;
  sample_interval_ = options.sample_interval;
  shared_.law.reset(m);
  shared_.local_tolerance = kLocalErrorShare * options.tolerance;
  for (std::size_t j = 0; j < m; ++j) {
    const LawConstants& law = laws[j];
    const double e2 = law.restitution * law.restitution;
    const bool mono = law.mono_stiffness;
    shared_.law.stiffness[j] = law.stiffness;
    shared_.law.exponent[j] = law.exponent;
    // expansion: d delta/dt = -u / e^2 (bi-stiffness) or -u (mono-stiffness)
    shared_.law.expansion_rate[j] = mono || e2 == 0.0 ? 1.0 : law.inverse_e2;
    // released at delta_c (1 - e^2)^(1/(1+eta)) (mono-stiffness) or at 0 (bi-stiffness)
    shared_.law.release_factor[j] = mono ? std::pow(1.0 - e2, 1.0 / law.one_plus_exponent) : 0.0;
    shared_.law.gives_nothing_back[j] = law.restitution == 0.0;
    // the natural scales of contact j: the impulse that stops V, the indentation that stores
    // the energy V^2 / (2 H_jj)
    const double h = diagonal(Index(j));
    shared_.law.self_mobility[j] = h;
    shared_.law.impulse_scale[j] = fastest / h;
    shared_.law.delta_scale[j] =
        std::pow((1.0 + law.exponent) * fastest * fastest / (2.0 * h * law.stiffness),
                 1.0 / (1.0 + law.exponent));
    shared_.law.energy_tolerance[j] =
        shared_.velocity_tolerance * shared_.velocity_tolerance / (2.0 * h);
  }
  shared_.contact.reset(u_minus);
  for (std::size_t j = 0; j < m; ++j)
    if (shared_.contact.velocity[j] < -shared_.velocity_tolerance)
      shared_.contact.phase[j] = Phase::compression;
  shared_.segment.members.clear();
  within_.prepare(laws, std::size_t(options.within_steps_from));
  friction_.prepare(input);
  steps_ = contact_steps_ = 0;
  segment_start_ = last_sample_ = closed_impulse_sum_ = 0.0;
}

// The members of the segment that starts now: the contacts holding energy, then the open
// contacts their forces reach through H. The ODE state starts at [delta / scale, 0].
void adaptive_lzb::Impact::begin_segment() {
  if (!friction_.on() && within_.choose()) {
    within_.begin_segment();
    size_segment();
    return;
  }
  for (Index j : shared_.segment.members) shared_.contact.member_of[j] = -1;
  std::vector<Index>& previous = shared_.segment.previous_members;
  previous.swap(shared_.segment.members);
  shared_.segment.members.clear();
  within_.hand_pending(previous);
  // the active contacts were members already (a contact becomes active only by a switch at a
  // member), so the new active set is found among the previous members, in their order
  for (Index j : previous)
    if (shared_.contact.phase[j] != Phase::open) {
      shared_.contact.member_of[j] = int(shared_.segment.members.size());
      shared_.segment.members.push_back(j);
    }
  if (previous.empty())  // the first segment
    for (Index j = 0; j < Index(shared_.contact.phase.size()); ++j)
      if (shared_.contact.phase[j] != Phase::open) {
        shared_.contact.member_of[j] = int(shared_.segment.members.size());
        shared_.segment.members.push_back(j);
      }
  shared_.segment.active = shared_.segment.members.size();
  const int* start = shared_.H->outerIndexPtr();
  const int* row = shared_.H->innerIndexPtr();
  for (std::size_t a = 0; a < shared_.segment.active; ++a)
    for (int k = start[shared_.segment.members[a]]; k < start[shared_.segment.members[a] + 1]; ++k)
      if (shared_.contact.member_of[row[k]] < 0) {
        shared_.contact.member_of[row[k]] = int(shared_.segment.members.size());
        shared_.segment.members.push_back(row[k]);
      }
  if (friction_.on()) friction_.add_reached();
  size_segment();
}

// The ODE state [delta / scale, 0] of the members that carry one, and the buffers.
void adaptive_lzb::Impact::size_segment() {
  shared_.segment.y.assign(2 * shared_.segment.active, 0.0);
  shared_.segment.y_at.assign(2 * shared_.segment.active, 0.0);
  shared_.segment.rate.resize(shared_.segment.active);
  for (std::size_t a = 0; a < shared_.segment.active; ++a) {
    const Index j = shared_.segment.members[a];
    shared_.segment.y[a] = shared_.contact.delta[j] / shared_.law.delta_scale[j];
    shared_.segment.rate[a] =
        shared_.contact.phase[j] == Phase::expansion ? shared_.law.expansion_rate[j] : 1.0;
  }
  shared_.segment.rhs_velocity.resize(shared_.segment.members.size());
  shared_.segment.velocity_at.resize(shared_.segment.members.size());
  shared_.segment.accounted_impulse.assign(shared_.segment.active, 0.0);
  shared_.segment.accounted_velocity.resize(shared_.segment.active);
  for (std::size_t a = 0; a < shared_.segment.active; ++a)
    shared_.segment.accounted_velocity[a] = shared_.contact.velocity[shared_.segment.members[a]];
  if (friction_.on()) friction_.size_segment();
}

// The contacts' work since the last accounting point, by the trapezoidal rule on u: per contact
// an approximation of the integral of -u_j dP_j, summed over them exact, since u is linear in P
// (the kinetic energy lost to round-off, docs/model.md section 12; docs/design/adaptive_lzb.md).
void adaptive_lzb::Impact::account_work(const State& y) {
  member_velocities(y, shared_.segment.velocity_at);
  for (std::size_t a = 0; a < shared_.segment.active; ++a) {
    const Index j = shared_.segment.members[a];
    const double impulse = y[shared_.segment.active + a] * shared_.law.impulse_scale[j];
    shared_.contact.work[j] -=
        0.5 * (shared_.segment.accounted_velocity[a] + shared_.segment.velocity_at[a]) *
        (impulse - shared_.segment.accounted_impulse[a]);
    shared_.segment.accounted_velocity[a] = shared_.segment.velocity_at[a];
    shared_.segment.accounted_impulse[a] = impulse;
  }
  if (friction_.on()) friction_.account_work(y);
}

// d delta_j/dt = -u_j (compression, mono-stiffness expansion) or -u_j / e_j^2 (bi-stiffness
// expansion); dP_j/dt = F_j = K_j delta_j^eta_j. Scaled by each contact's delta and P scales.
void adaptive_lzb::Impact::derivative(const State& y, State& dydt) {
  member_velocities(y, shared_.segment.rhs_velocity);
  for (std::size_t a = 0; a < shared_.segment.active; ++a) {
    const Index j = shared_.segment.members[a];
    dydt[a] =
        -shared_.segment.rhs_velocity[a] * shared_.segment.rate[a] / shared_.law.delta_scale[j];
    dydt[shared_.segment.active + a] =
        shared_.law.force(j, shared_.delta_of(a, y)) / shared_.law.impulse_scale[j];
  }
  if (friction_.on()) friction_.derivative(y, dydt);
}

// Writes the members' state at the end of the segment (state y) into the per-contact arrays.
void adaptive_lzb::Impact::end_segment(const State& y) {
  member_velocities(y, shared_.segment.velocity_at);
  for (std::size_t p = 0; p < shared_.segment.members.size(); ++p)
    shared_.contact.velocity[shared_.segment.members[p]] = shared_.segment.velocity_at[p];
  for (std::size_t a = 0; a < shared_.segment.active; ++a) {
    const Index j = shared_.segment.members[a];
    shared_.contact.delta[j] = shared_.delta_of(a, y);
    const double increment = y[shared_.segment.active + a] * shared_.law.impulse_scale[j];
    shared_.contact.impulse[j] += increment;
    closed_impulse_sum_ += increment;
    if (within_.on()) within_.end_member(a, increment);
  }
  if (friction_.on()) friction_.end_segment(y);
}

void adaptive_lzb::Impact::apply(const std::vector<Crossing>& crossings, double t) {
  for (const Crossing& crossing : crossings) {
    if (crossing.kind >= slip_stop) {
      friction_.apply(crossing);
      continue;
    }
    const Index j = shared_.segment.members[std::size_t(crossing.index)];
    switch (crossing.kind) {
      case join:
        shared_.contact.phase[j] = Phase::compression;
        shared_.contact.delta[j] = 0.0;
        break;
      case compression_end:
        if (const double f = shared_.law.force(j, shared_.contact.delta[j]);
            f > shared_.contact.max_force[j]) {
          shared_.contact.max_force[j] = f;
          shared_.contact.time_of_max[j] = t;
        }
        shared_.contact.phase[j] =
            shared_.law.gives_nothing_back[j] ? Phase::open : Phase::expansion;
        if (shared_.law.gives_nothing_back[j]) shared_.contact.delta[j] = 0.0;
        shared_.contact.release_level[j] = shared_.law.release_factor[j] * shared_.contact.delta[j];
        break;
      case reload:
        shared_.contact.phase[j] = Phase::compression;
        break;
      default:  // release
        shared_.contact.phase[j] = Phase::open;
        shared_.contact.delta[j] = 0.0;
        break;
    }
  }
}

// The impact's end: no contact approaches faster than tolerance * V and none holds more
// than its energy tolerance (the open ones are known to approach slower: they would have
// joined).
bool adaptive_lzb::Impact::settled(const State& y) {
  member_velocities(y, shared_.segment.velocity_at);
  for (std::size_t a = 0; a < shared_.segment.active; ++a) {
    const Index j = shared_.segment.members[a];
    if (shared_.segment.velocity_at[a] < -shared_.velocity_tolerance ||
        shared_.law.energy(j, shared_.delta_of(a, y)) > shared_.law.energy_tolerance[j])
      return false;
  }
  return true;
}

void adaptive_lzb::Impact::notify(double t, const State* y, ImpactObserver& observer) {
  if (y) member_velocities(*y, shared_.segment.velocity_at);
  double impulse_sum = closed_impulse_sum_;
  if (y)
    for (std::size_t a = 0; a < shared_.segment.active; ++a)
      impulse_sum +=
          (*y)[shared_.segment.active + a] * shared_.law.impulse_scale[shared_.segment.members[a]];
  const auto value_of = [&](Index j, double& u, double& energy_now, double& force_now,
                            double& impulse) {
    const int p = y ? shared_.contact.member_of[j] : -1;
    const bool active = p >= 0 && std::size_t(p) < shared_.segment.active;
    const double delta = active ? shared_.delta_of(std::size_t(p), *y) : shared_.contact.delta[j];
    u = p >= 0 ? shared_.segment.velocity_at[std::size_t(p)] : shared_.contact.velocity[j];
    energy_now = shared_.law.energy(j, delta);
    force_now = shared_.law.force(j, delta);
    impulse = shared_.contact.impulse[j] +
              (active ? (*y)[shared_.segment.active + std::size_t(p)] * shared_.law.impulse_scale[j]
                      : 0.0);
  };
  if (friction_.on())
    sampler_->observe(observer, steps_, t, impulse_sum, value_of,
                      [&](Index row) { return friction_.tangential_impulse(row, y); });
  else
    sampler_->observe(observer, steps_, t, impulse_sum, value_of);
}

// The samples of the observer that fall in the part of the current step up to t.
void adaptive_lzb::Impact::sample_until(double t, ImpactObserver& observer) {
  if (sample_interval_ <= 0.0) return;
  for (double next = last_sample_ + sample_interval_; next <= t;
       next = last_sample_ + sample_interval_) {
    ode_.state_at(next, shared_.segment.y_at);
    notify(next, &shared_.segment.y_at, observer);
    last_sample_ = next;
  }
}

void adaptive_lzb::Impact::finish(double t, ImpactResult& result) {
  const std::size_t m = shared_.contact.phase.size();
  result.impulse = Eigen::Map<const Eigen::VectorXd>(shared_.contact.impulse.data(), Index(m));
  result.work = Eigen::Map<const Eigen::VectorXd>(shared_.contact.work.data(), Index(m));
  result.stored_energy = Eigen::VectorXd::Zero(Index(m));
  for (std::size_t j = 0; j < m; ++j) {
    if (shared_.contact.phase[j] == Phase::open) continue;
    result.stored_energy(Index(j)) = shared_.law.energy(Index(j), shared_.contact.delta[j]);
    if (const double f = shared_.law.force(Index(j), shared_.contact.delta[j]);
        f > shared_.contact.max_force[j]) {
      shared_.contact.max_force[j] = f;  // still in compression at the end
      shared_.contact.time_of_max[j] = t;
    }
  }
  result.max_force = Eigen::Map<const Eigen::VectorXd>(shared_.contact.max_force.data(), Index(m));
  result.time_of_max_force =
      Eigen::Map<const Eigen::VectorXd>(shared_.contact.time_of_max.data(), Index(m));
  if (friction_.on()) friction_.finish(result);
  result.steps = steps_;
  result.contact_steps = contact_steps_;
  result.duration = t;
}

std::string adaptive_lzb::Impact::budget_spent(const LzbAdaptiveOptions& options,
                                               std::int64_t restarts,
                                               std::int64_t most_events) const {
  if (restarts >= most_events)
    return "the impact did not end within " + std::to_string(most_events) +
           " located events (events_per_contact = " + std::to_string(options.events_per_contact) +
           " a contact, at least 100000) by t = " + to_text(ode_.time()) +
           " s of the impact: bodies rattle between others without their events thinning out; "
           "raise events_per_contact (impact.events_per_contact in a scene) to go on, or give "
           "the rattling bodies the mass they need";
  if (steps_ + restarts >= options.max_steps)
    return "the impact did not end within max_steps = " + std::to_string(options.max_steps) +
           " steps and restarts";
  return "";
}

void adaptive_lzb::Impact::stop_at_budget(const std::string& message, ImpactObserver* observer,
                                          ImpactResult& result) {
  account_work(ode_.state());
  end_segment(ode_.state());
  finish(ode_.time(), result);
  result.status = ImpactStatus::step_limit;
  result.message = message;
  if (observer) notify(result.duration, nullptr, *observer);
}

void adaptive_lzb::Impact::run(const ImpactIntegrator::Input& input,
                               const LzbAdaptiveOptions& options, ImpactSampler& sampler,
                               ImpactObserver* observer, ImpactResult& result) {
  const Eigen::VectorXd& u_minus = input.u_minus;
  shared_.H = &input.H;
  sampler_ = &sampler;
  prepare(input, options);
  begin_segment();
  // the first step: a small share of the time the fastest contact takes to stop
  double first_step = 1.0;
  for (std::size_t a = 0; a < shared_.segment.active; ++a)
    if (u_minus(shared_.segment.members[a]) < 0.0)
      first_step = std::min(first_step, shared_.law.delta_scale[shared_.segment.members[a]] /
                                            -u_minus(shared_.segment.members[a]));
  ode_.restart(shared_.segment.y, 0.0, 1e-3 * first_step);
  if (observer) notify(0.0, &shared_.segment.y, *observer);
  auto rhs = [this](const State& y, State& dydt, double) { derivative(y, dydt); };

  std::int64_t restarts = 0;
  const std::int64_t most_events =
      std::max(LzbAdaptiveOptions::kLeastEvents,
               options.events_per_contact * std::int64_t(shared_.law.delta_scale.size()));
  double t = 0.0;
  while (true) {
    const std::string spent = budget_spent(options, restarts, most_events);
    if (!spent.empty()) {
      stop_at_budget(spent, observer, result);
      return;
    }
    const double step_start = ode_.time();
    ode_.step(rhs);
    ++steps_;
    contact_steps_ += std::int64_t(shared_.segment.active);
    if (observer) observer->progressed({.step = steps_, .time = ode_.time()});
    const std::vector<Crossing> found = scan_events(
        {.start = step_start, .end = ode_.time(), .samples = kSamplesPerStep + 1},
        shared_.segment.before, shared_.segment.after,
        [this](double time, Watched& v) { watch(time, v); },
        [this](double t0, double t1, const Watched& b, const Watched& a, std::vector<Crossing>& f) {
          locate(t0, t1, b, a, f);
        });
    if (found.empty()) {
      t = ode_.time();
      const bool changed = within_.on() && within_.settle_turns(step_start, t);
      const State& y = changed ? within_.settled() : ode_.state();
      account_work(y);
      if (observer) sample_until(t, *observer);
      const bool grow = within_.on() && within_.outgrown(y);
      if (!grow && settled(y)) {
        end_segment(y);
        break;
      }
      if (changed || grow) {
        // a state set back, or members to add: the same step goes on from here
        end_segment(y);
        begin_segment();
        if (shared_.segment.active == 0) break;
        ode_.restart(shared_.segment.y, t, ode_.next_step());
        segment_start_ = t;
      }
      continue;
    }
    t = found.front().time;
    if (observer) sample_until(t, *observer);
    ode_.state_at(t, shared_.segment.y_at);
    account_work(shared_.segment.y_at);
    end_segment(shared_.segment.y_at);
    apply(found, t);
    const double last_step = ode_.last_step();
    begin_segment();
    if (shared_.segment.active == 0) break;
    ode_.restart(shared_.segment.y, t, last_step);
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

bool LzbAdaptiveIntegrator::integrates_friction() const { return true; }

void LzbAdaptiveIntegrator::run(const Input& input, ImpactObserver* observer,
                                ImpactResult& result) {
  if (!impact_) impact_ = std::make_unique<Impact>(options_.tolerance);
  impact_->run(input, options_, sampler(), observer, result);
}

}  // namespace mimpact::numerics
