#include "mimpact/plugins/event_driven_integrator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "event_driven_motion.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/numerics/dense_output.hpp"
#include "mimpact/numerics/event_scan.hpp"
#include "mimpact/numerics/root_bracketing.hpp"

namespace mimpact::plugins {

using numerics::Crossing;

EventDrivenIntegrator::EventDrivenIntegrator(EventDrivenOptions options) : options_(options) {
  validate(options_, "event-driven integrator");
}

EventDrivenIntegrator::~EventDrivenIntegrator() = default;

void EventDrivenIntegrator::initialize(kernel::NonSmoothDynamicalSystem& system, double start,
                                       const kernel::EventProblems& problems) {
  if (!problems.impacts || !problems.contact_forces)
    throw InvalidInput("event-driven integrator: needs an impact and a contact force problem");
  system_ = &system;
  impacts_ = problems.impacts;
  forces_ = problems.contact_forces;
  time_ = start;
  system.gather_state(q_, v_);
  motion_ = std::make_unique<Motion>();
  motion_->dynamics.initialize(system);
  motion_->friction.initialize(system, options_.velocity_tolerance);
  const Index m = system.interaction_count();
  for (Watched* watched : {&motion_->before, &motion_->after, &motion_->probed}) {
    watched->gaps.setZero(m);
    watched->rates.setZero(m);
  }
  velocity_resolution_.setZero(m);
  last_event_time_ = -std::numeric_limits<double>::infinity();
  events_at_instant_ = 0;

  closed_.clear();
  for (Index j = 0; j < m; ++j)
    if (system.gap(j, q_) <= options_.gap_tolerance) closed_.push_back(j);
  system.index_sets().closed = closed_;
  system.index_sets().persistent.clear();
  impact_pending_ = false;
  for (Index j : closed_)
    impact_pending_ = impact_pending_ || system.velocity(j, q_, v_) < -options_.velocity_tolerance;
  settle_pending_ = !impact_pending_ && !closed_.empty();
  free_flight_ = !system.has_force();
}

kernel::StepReport EventDrivenIntegrator::advance(double target) {
  kernel::StepReport report;
  report.time = time_;
  if (settle_pending_) {
    settle_pending_ = false;
    settle(report);
  }
  if (impact_pending_) {  // closed contacts approach now: an impact at this very instant
    impact_pending_ = false;
    process_event({time_, {}, {}, {}}, report);
    return report;
  }
  if (target <= time_) return report;
  while (true) {
    const double end = std::min(known_until(report), target);
    Event event;
    if (search(time_, end, event)) {
      move_to(event.time);
      if (event.closing.empty() && event.detaching.empty()) {
        switch_phases(event);
        continue;
      }
      process_event(event, report);
      return report;
    }
    move_to(end);
    if (end >= target) {
      system_->scatter_state(q_, v_);
      report.time = time_;
      return report;
    }
  }
}

double EventDrivenIntegrator::known_until(kernel::StepReport& report) {
  if (free_flight_) return std::numeric_limits<double>::infinity();
  if (!motion_->dense || !motion_->dense->started()) restart_motion();
  numerics::DenseOutput& dense = *motion_->dense;
  while (dense.time() <= time_) {
    dense.step([this](const std::vector<double>& y, std::vector<double>& dydt, double t) {
      derivative(y, dydt, t);
    });
    ++report.smooth_steps;
  }
  return dense.time();
}

void EventDrivenIntegrator::derivative(const std::vector<double>& y, std::vector<double>& dydt,
                                       double t) {
  const Index n = system_->dof();
  Motion& m = *motion_;
  m.q = Eigen::Map<const VectorXd>(y.data(), n);
  m.v = Eigen::Map<const VectorXd>(y.data() + n, n);
  const std::vector<Index>& persistent = system_->index_sets().persistent;
  m.dynamics.evaluate(t, m.q, m.v, persistent);
  if (persistent.empty()) {
    m.a = m.dynamics.free_acceleration();
  } else if (m.friction.rubbing()) {
    m.friction.accelerate(m.dynamics, m.q, m.v, m.a, m.normal);
  } else {
    m.dynamics.acceleration(m.dynamics.bilateral_force(), m.a);
  }
  Eigen::Map<VectorXd>(dydt.data(), n) = m.v;
  Eigen::Map<VectorXd>(dydt.data() + n, n) = m.a;
}

void EventDrivenIntegrator::restart_motion() {
  Motion& m = *motion_;
  if (!m.dense) m.dense.emplace(options_.ode);
  const Index n = system_->dof();
  m.y.resize(2 * n);
  m.probe.resize(2 * n);
  Eigen::Map<VectorXd>(m.y.data(), n) = q_;
  Eigen::Map<VectorXd>(m.y.data() + n, n) = v_;
  const double first_step = m.dense->last_step() > 0.0 ? m.dense->last_step() : 1e-4;
  m.dense->restart(m.y, time_, first_step);
}

void EventDrivenIntegrator::move_to(double t) {
  state_at(t, q_, v_);
  time_ = t;
}

void EventDrivenIntegrator::state_at(double t, VectorXd& q, VectorXd& v) {
  if (free_flight_) {
    q = q_ + (t - time_) * v_;
    v = v_;
    return;
  }
  const Index n = system_->dof();
  Motion& m = *motion_;
  m.dense->state_at(t, m.probe);
  q = Eigen::Map<const VectorXd>(m.probe.data(), n);
  v = Eigen::Map<const VectorXd>(m.probe.data() + n, n);
}

void EventDrivenIntegrator::watch(double t, Watched& values) {
  Motion& m = *motion_;
  state_at(t, m.q_probe, m.v_probe);
  const std::vector<Index>& persistent = system_->index_sets().persistent;
  for (Index j = 0; j < system_->interaction_count(); ++j) {
    values.gaps(j) = system_->gap(j, m.q_probe);
    values.rates(j) = system_->velocity(j, m.q_probe, m.v_probe);
  }
  if (persistent.empty()) return;
  if (free_flight_) {  // no force, constant W: nothing presses a persistent contact
    values.forces.setZero(Index(persistent.size()));
    values.friction.setOnes(0);
    return;
  }
  m.dynamics.evaluate(t, m.q_probe, m.v_probe, persistent);
  if (!m.friction.rubbing()) {
    values.forces = m.dynamics.bilateral_force();
    values.friction.resize(0);
    return;
  }
  m.friction.accelerate(m.dynamics, m.q_probe, m.v_probe, m.a, values.forces);
  m.friction.watched(values.friction);
}

double EventDrivenIntegrator::gap_function(Index j, double t) {
  Motion& m = *motion_;
  state_at(t, m.q_probe, m.v_probe);
  return system_->gap(j, m.q_probe);
}

double EventDrivenIntegrator::rate_function(Index j, double t) {
  Motion& m = *motion_;
  state_at(t, m.q_probe, m.v_probe);
  return system_->velocity(j, m.q_probe, m.v_probe);
}

double EventDrivenIntegrator::force_function(Index k, double t) {
  Motion& m = *motion_;
  state_at(t, m.q_probe, m.v_probe);
  m.dynamics.evaluate(t, m.q_probe, m.v_probe, system_->index_sets().persistent);
  if (!m.friction.rubbing()) return m.dynamics.bilateral_force()(k);
  m.friction.accelerate(m.dynamics, m.q_probe, m.v_probe, m.a, m.normal);
  return m.normal(k);
}

double EventDrivenIntegrator::friction_function(Index value, double t) {
  Motion& m = *motion_;
  watch(t, m.probed);
  return m.probed.friction(value);
}

// Past switches of the rubbing contacts' Coulomb phases (a slip stopped, a stick ended): the
// phases settled there, and the smooth motion restarted.
void EventDrivenIntegrator::switch_phases(const Event& event) {
  check_event_loop(time_);
  Motion& m = *motion_;
  for (Index value : event.switches) m.friction.pass(std::size_t(value / 2), int(value % 2));
  m.friction.settle(time_, q_, v_, m.dynamics);
  m.phases_since = time_;
  if (m.dense) m.dense->invalidate();
}

double EventDrivenIntegrator::closing_time(Index j, double t0, double t1, const Watched& before,
                                           const Watched& after, double& level) {
  const double tolerance = options_.ode.event_tolerance;
  const double g0 = before.gaps(j), g1 = after.gaps(j), u0 = before.rates(j), u1 = after.rates(j);
  // between two samples the gap has at most one turn, found where its rate u changes sign
  auto turn = [&](double sign) {  // the time of the turn: u crosses 0 from sign*u > 0
    return numerics::narrow_crossing([&](double s) { return sign * rate_function(j, s); }, t0, t1,
                                     sign * u0, sign * u1, tolerance)
        .upper;
  };
  auto crossing = [&](double lower, double upper, double f_lower, double f_upper) {
    return numerics::narrow_crossing([&](double s) { return gap_function(j, s) - level; }, lower,
                                     upper, f_lower, f_upper, tolerance)
        .upper;
  };
  if (level < 0.0 && u0 > 0.0 && u1 < 0.0) {
    // a closed contact rising and falling back: if it opened, it closes when it reaches 0
    const double top = turn(1.0);
    const double g_top = gap_function(j, top);
    if (g_top > 0.0) {
      level = 0.0;
      return g1 > 0.0 ? std::numeric_limits<double>::infinity() : crossing(top, t1, g_top, g1);
    }
  }
  const double f0 = g0 - level, f1 = g1 - level;
  if (f0 > 0.0 && f1 <= 0.0) return crossing(t0, t1, f0, f1);
  if (f0 > 0.0 && u0 < 0.0 && u1 > 0.0) {
    // above the level at both samples: it may dip below in between, around a minimum
    const double bottom = turn(-1.0);
    const double f_bottom = gap_function(j, bottom) - level;
    if (f_bottom <= 0.0) return crossing(t0, bottom, f0, f_bottom);
  }
  if (g1 > 0.0) level = 0.0;  // it has opened
  return std::numeric_limits<double>::infinity();
}

bool EventDrivenIntegrator::search(double a, double b, Event& event) {
  Motion& m = *motion_;
  const std::vector<Index>& persistent = system_->index_sets().persistent;
  std::vector<char> held(std::size_t(system_->interaction_count()), 0);
  for (Index j : persistent) held[std::size_t(j)] = 1;
  const double tolerance = options_.ode.event_tolerance;
  enum Kind { closing, detaching, switching };
  auto watch_at = [this](double t, Watched& values) { watch(t, values); };
  bool levels_set = false;
  auto locate = [&](double t0, double t1, const Watched& before, const Watched& after,
                    std::vector<Crossing>& found) {
    // an open contact closes when its gap reaches 0; one that starts closed (and is not held)
    // when it sinks a gap tolerance below where it starts, or reaches 0 again after opening
    if (!levels_set) {
      m.levels.resize(before.gaps.size());
      for (Index j = 0; j < before.gaps.size(); ++j)
        m.levels(j) =
            before.gaps(j) > 0.0 ? 0.0 : before.gaps(j) - std::max(options_.gap_tolerance, 1e-300);
      levels_set = true;
    }
    for (Index j = 0; j < system_->interaction_count(); ++j) {
      if (held[std::size_t(j)]) continue;
      const double time = closing_time(j, t0, t1, before, after, m.levels(j));
      if (time < std::numeric_limits<double>::infinity()) found.push_back({j, closing, time});
    }
    for (std::size_t p = 0; p < persistent.size(); ++p) {
      const Index k = Index(p);
      if (!(before.forces(k) > 0.0 && after.forces(k) <= 0.0)) continue;
      const numerics::Bracket crossing =
          numerics::narrow_crossing([&](double s) { return force_function(k, s); }, t0, t1,
                                    before.forces(k), after.forces(k), tolerance);
      found.push_back({persistent[p], detaching, crossing.upper});
    }
    for (Index value = 0; value < before.friction.size(); ++value) {
      const std::optional<double> crossing = numerics::crossing_time(
          before.friction(value), after.friction(value), t0, t1, m.phases_since,
          [&](double s) { return friction_function(value, s); });
      if (crossing) found.push_back({value, switching, *crossing});
    }
  };
  const std::vector<Crossing> found = numerics::scan_events(
      {.start = a, .end = b, .samples = options_.ode.samples_per_step, .tolerance = tolerance},
      m.before, m.after, watch_at, locate);
  if (found.empty()) return false;
  event = {found.front().time, {}, {}, {}};
  for (const Crossing& crossing : found) {
    event.time = std::min(event.time, crossing.time);
    (crossing.kind == detaching   ? event.detaching
     : crossing.kind == switching ? event.switches
                                  : event.closing)
        .push_back(crossing.index);
  }
  return true;
}

void EventDrivenIntegrator::check_event_loop(double t) {
  if (t - last_event_time_ <= options_.ode.event_tolerance) {
    if (++events_at_instant_ > options_.max_events_at_one_instant)
      throw Error("more than " + std::to_string(options_.max_events_at_one_instant) +
                  " events at t = " + to_text(t) +
                  " s: the contacts never settle; raise rest_flight_time or check the model");
  } else {
    events_at_instant_ = 1;
  }
  last_event_time_ = t;
}

void EventDrivenIntegrator::process_event(const Event& event, kernel::StepReport& report) {
  check_event_loop(event.time);
  time_ = event.time;
  system_->scatter_state(q_, v_);
  report.time = time_;
  report.event = true;
  report.closing = event.closing;
  report.detaching = event.detaching;

  // I_c: contacts within the gap tolerance, and those whose gap was found crossing 0
  closed_.clear();
  for (Index j = 0; j < system_->interaction_count(); ++j)
    if (system_->gap(j, q_) <= options_.gap_tolerance ||
        std::find(event.closing.begin(), event.closing.end(), j) != event.closing.end())
      closed_.push_back(j);
  system_->index_sets().closed = closed_;

  bool impact = false;
  for (Index j : closed_)
    impact = impact || system_->velocity(j, q_, v_) < -options_.velocity_tolerance;
  velocity_resolution_.setZero();
  if (impact) {
    kernel::ImpactReport solved = impacts_->solve(*system_, closed_, time_);
    if (solved.result.status != numerics::ImpactStatus::terminated)
      throw Error("impact at t = " + to_text(time_) + " s: " + solved.result.message);
    system_->gather_state(q_, v_);
    if (solved.velocity_resolution.size() == Index(closed_.size()))
      for (std::size_t k = 0; k < closed_.size(); ++k)
        velocity_resolution_(closed_[k]) = solved.velocity_resolution(Index(k));
    report.impact = std::move(solved);
  }
  settle_pending_ = true;
  if (motion_->dense) motion_->dense->invalidate();
}

kernel::ContactForces EventDrivenIntegrator::persistent_forces() {
  kernel::ContactForces forces;
  const std::vector<Index>& persistent = system_->index_sets().persistent;
  forces.time = time_;
  forces.interactions = persistent;
  forces.solved = true;
  if (persistent.empty()) return forces;
  motion_->dynamics.evaluate(time_, q_, v_, persistent);
  if (motion_->friction.rubbing()) {
    motion_->friction.accelerate(motion_->dynamics, q_, v_, motion_->a, forces.force);
  } else {
    forces.force = motion_->dynamics.bilateral_force();
  }
  forces.acceleration = VectorXd::Zero(forces.force.size());
  return forces;
}

}  // namespace mimpact::plugins
