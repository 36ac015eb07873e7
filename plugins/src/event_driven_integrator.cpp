#include "mimpact/plugins/event_driven_integrator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "contact_dynamics.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/numerics/dense_output.hpp"
#include "mimpact/numerics/event_scan.hpp"
#include "mimpact/numerics/root_bracketing.hpp"

namespace mimpact::plugins {

using numerics::Crossing;

// What the event search watches at one time: every contact's gap (m) and normal velocity
// (m/s), and the force holding each persistent contact (N).
struct EventDrivenIntegrator::Watched {
  VectorXd gaps, rates, forces;
};

// The smooth motion: the contact dynamics with the persistent contacts held, its integration
// (Dormand-Prince 5(4) with dense output, on y = (q, v); only once some force acts), and the
// event search's workspace.
struct EventDrivenIntegrator::Motion {
  ContactDynamics dynamics;
  std::optional<numerics::DenseOutput> dense;
  numerics::DenseOutput::State y, probe;
  VectorXd q, v, a;  // right-hand side workspace
  VectorXd q_probe, v_probe;
  Watched before, after;
  VectorXd levels;  // the gap at which each contact counts as closing, in a search
};

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
  const Index m = system.interaction_count();
  for (Watched* watched : {&motion_->before, &motion_->after}) {
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
    process_event({time_, {}, {}}, report);
    return report;
  }
  if (target <= time_) return report;
  while (true) {
    const double end = std::min(known_until(report), target);
    Event event;
    if (search(time_, end, event)) {
      move_to(event.time);
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
    return;
  }
  m.dynamics.evaluate(t, m.q_probe, m.v_probe, persistent);
  values.forces = m.dynamics.bilateral_force();
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
  return m.dynamics.bilateral_force()(k);
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
  enum Kind { closing, detaching };
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
  };
  const std::vector<Crossing> found = numerics::scan_events(
      {.start = a, .end = b, .samples = options_.ode.samples_per_step, .tolerance = tolerance},
      m.before, m.after, watch_at, locate);
  if (found.empty()) return false;
  event = {found.front().time, {}, {}};
  for (const Crossing& crossing : found) {
    event.time = std::min(event.time, crossing.time);
    (crossing.kind == detaching ? event.detaching : event.closing).push_back(crossing.index);
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

// Algorithm 6 of Nguyen & Brogliato (2011), before the next smooth motion: penetrations are
// undone, contacts come to rest, and the contact force problem decides which stay closed.
// A contact sent into a real approach by any of this makes an impact now instead.
void EventDrivenIntegrator::settle(kernel::StepReport& report) {
  restore_penetrations();
  const std::vector<Index> resting = bring_to_rest();
  if (impact_pending_) {
    system_->scatter_state(q_, v_);
    return;
  }
  hold_resting(resting, report);
}

// Events are placed just after a crossing, so closed contacts penetrate a little, and a
// contact that closes again while already closed sinks deeper each time: the least
// mass-weighted shift of positions, dq = M^-1 W lambda with H lambda = -g over the
// penetrating contacts, brings them back to g = 0. Shifting one may press a neighbour in:
// the set grows until no closed contact penetrates.
void EventDrivenIntegrator::restore_penetrations() {
  ContactDynamics& dynamics = motion_->dynamics;
  std::vector<Index> penetrating;
  for (std::size_t round = 0; round <= closed_.size(); ++round) {
    bool added = false;
    for (Index j : closed_)
      if (system_->gap(j, q_) < 0.0 &&
          std::find(penetrating.begin(), penetrating.end(), j) == penetrating.end()) {
        penetrating.push_back(j);
        added = true;
      }
    if (!added) break;
    VectorXd g(Index(penetrating.size()));
    for (std::size_t k = 0; k < penetrating.size(); ++k)
      g(Index(k)) = system_->gap(penetrating[k], q_);
    dynamics.evaluate(time_, q_, v_, penetrating);
    const VectorXd shift = dynamics.solve(-g);
    dynamics.add_mobility_times(shift, q_);
  }
}

// Contacts come to rest when |u| is within what the last impact resolves or their next
// flight would be too short; the least-energy velocity change then sets their u to 0. That
// change moves the other closed contacts too, so the classification repeats until nothing
// changes. Sets impact_pending_ when a closed contact approaches for real.
std::vector<Index> EventDrivenIntegrator::bring_to_rest() {
  ContactDynamics& dynamics = motion_->dynamics;
  std::vector<Index> resting;
  std::vector<char> rests(std::size_t(system_->interaction_count()), 0);
  for (std::size_t round = 0; round <= closed_.size(); ++round) {
    dynamics.evaluate(time_, q_, v_, {});
    const VectorXd& free_acceleration = dynamics.free_acceleration();
    bool added = false;
    for (Index j : closed_) {
      if (rests[std::size_t(j)]) continue;
      const double u = system_->velocity(j, q_, v_);
      // an impact may leave a contact approaching as slowly as its velocity resolution:
      // that is rest, not a new impact; a separation, however slow, is real unless its
      // flight would be shorter than rest_flight_time
      const double resolution = std::max(options_.velocity_tolerance, velocity_resolution_(j));
      if (u < -resolution) {
        impact_pending_ = true;
        return resting;
      }
      double b = system_->jacobian_rate(j, q_, v_);
      system_->for_each_jacobian_entry(j, q_,
                                       [&](Index i, double w) { b += w * free_acceleration(i); });
      const double rest_speed = b < 0.0 ? 0.5 * -b * options_.rest_flight_time : 0.0;
      if (u <= std::max(options_.velocity_tolerance, rest_speed)) {
        resting.push_back(j);
        rests[std::size_t(j)] = 1;
        added = true;
      }
    }
    if (!added) break;
    VectorXd u(Index(resting.size()));
    for (std::size_t k = 0; k < resting.size(); ++k)
      u(Index(k)) = system_->velocity(resting[k], q_, v_);
    if (u.cwiseAbs().maxCoeff() > 0.0) {
      dynamics.evaluate(time_, q_, v_, resting);
      const VectorXd impulse = dynamics.solve(-u);
      dynamics.add_mobility_times(impulse, v_);
    }
  }
  return resting;
}

// Which resting contacts stay closed: the acceleration-level problem. They are held in the
// smooth motion that follows, which is q + v t when no force acts and every held relation is
// linear.
void EventDrivenIntegrator::hold_resting(const std::vector<Index>& resting,
                                         kernel::StepReport& report) {
  std::vector<Index> persistent;
  if (!resting.empty()) {
    kernel::ContactForces forces = forces_->solve(*system_, resting, time_, q_, v_);
    if (!forces.solved)
      throw Error("contact forces at t = " + to_text(time_) + " s: " + forces.message);
    // a contact pulled away more slowly than this would separate less than the velocity
    // tolerance over a rest flight time: it stays
    const double acceleration_tolerance =
        options_.rest_flight_time > 0.0
            ? 2.0 * options_.velocity_tolerance / options_.rest_flight_time
            : 0.0;
    for (std::size_t k = 0; k < resting.size(); ++k)
      if (forces.force(Index(k)) > 0.0 || forces.acceleration(Index(k)) <= acceleration_tolerance)
        persistent.push_back(resting[k]);
    report.contact_forces = std::move(forces);
  }
  system_->index_sets().persistent = persistent;
  system_->scatter_state(q_, v_);

  bool linear = true;
  for (Index j : persistent) linear = linear && system_->interaction(j).relation().is_linear();
  free_flight_ = !system_->has_force() && linear;
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
  forces.force = motion_->dynamics.bilateral_force();
  forces.acceleration = VectorXd::Zero(forces.force.size());
  return forces;
}

}  // namespace mimpact::plugins
