#include "mimpact/plugins/event_driven_integrator.hpp"

#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <limits>

#include "mimpact/numerics/error.hpp"
#include "mimpact/numerics/root_bracketing.hpp"

namespace mimpact::plugins {

namespace odeint = boost::numeric::odeint;

bool EventDrivenOptions::is_valid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  auto positive = [](double x) { return x > 0.0 && std::isfinite(x); };
  if (!positive(absolute_tolerance))
    return fail(invalid_value_message("absolute_tolerance", absolute_tolerance, "> 0"));
  if (!positive(relative_tolerance))
    return fail(invalid_value_message("relative_tolerance", relative_tolerance, "> 0"));
  if (!(max_step >= 0.0))
    return fail(invalid_value_message("max_step", max_step, ">= 0 (s, 0 for no limit)"));
  if (!positive(event_tolerance))
    return fail(invalid_value_message("event_tolerance", event_tolerance, "> 0 (s)"));
  if (samples_per_step < 1)
    return fail(invalid_value_message("samples_per_step", samples_per_step, ">= 1"));
  if (!(gap_tolerance >= 0.0))
    return fail(invalid_value_message("gap_tolerance", gap_tolerance, ">= 0 (m)"));
  if (!(velocity_tolerance >= 0.0))
    return fail(invalid_value_message("velocity_tolerance", velocity_tolerance, ">= 0 (m/s)"));
  if (!(rest_flight_time >= 0.0))
    return fail(invalid_value_message("rest_flight_time", rest_flight_time, ">= 0 (s)"));
  if (max_events_at_one_instant < 1)
    return fail(invalid_value_message("max_events_at_one_instant", max_events_at_one_instant,
                                      ">= 1"));
  return true;
}

// The smooth integration: Dormand-Prince 5(4) with dense output, on y = (q, v).
struct EventDrivenIntegrator::Ode {
  using State = std::vector<double>;
  using Stepper = odeint::runge_kutta_dopri5<State>;
  using Dense = odeint::result_of::make_dense_output<Stepper>::type;

  explicit Ode(const EventDrivenOptions& options)
      : dense(options.max_step > 0.0
                  ? odeint::make_dense_output(options.absolute_tolerance,
                                              options.relative_tolerance, options.max_step,
                                              Stepper())
                  : odeint::make_dense_output(options.absolute_tolerance,
                                              options.relative_tolerance, Stepper())) {}

  Dense dense;
  State y, probe;
  VectorXd q, v, a;  // right-hand side workspace
  bool started = false;
  double last_step = 0.0;
};

EventDrivenIntegrator::EventDrivenIntegrator(EventDrivenOptions options) : options_(options) {
  std::string why;
  if (!options_.is_valid(&why)) throw InvalidInput("event-driven integrator: " + why);
}

EventDrivenIntegrator::~EventDrivenIntegrator() = default;

std::unique_ptr<kernel::OneStepIntegrator> EventDrivenIntegrator::create(
    const kernel::Parameters& parameters) {
  parameters.allow_only("integrator \"event-driven\"",
                        {"absolute_tolerance", "relative_tolerance", "max_step",
                         "event_tolerance", "samples_per_step", "gap_tolerance",
                         "velocity_tolerance", "rest_flight_time", "max_events_at_one_instant"});
  EventDrivenOptions o;
  o.absolute_tolerance = parameters.get("absolute_tolerance", o.absolute_tolerance);
  o.relative_tolerance = parameters.get("relative_tolerance", o.relative_tolerance);
  o.max_step = parameters.get("max_step", o.max_step);
  o.event_tolerance = parameters.get("event_tolerance", o.event_tolerance);
  o.samples_per_step = int(parameters.get_integer("samples_per_step", o.samples_per_step, 1, 1'000'000));
  o.gap_tolerance = parameters.get("gap_tolerance", o.gap_tolerance);
  o.velocity_tolerance = parameters.get("velocity_tolerance", o.velocity_tolerance);
  o.rest_flight_time = parameters.get("rest_flight_time", o.rest_flight_time);
  o.max_events_at_one_instant =
      int(parameters.get_integer("max_events_at_one_instant", o.max_events_at_one_instant, 1,
                                 std::numeric_limits<int>::max()));
  return std::make_unique<EventDrivenIntegrator>(o);
}

void EventDrivenIntegrator::initialize(kernel::NonSmoothDynamicalSystem& system, double start,
                                       kernel::ImpactProblem& impacts,
                                       kernel::ContactForceProblem& forces) {
  system_ = &system;
  impacts_ = &impacts;
  forces_ = &forces;
  time_ = start;
  system.gather_state(q_, v_);
  dynamics_.initialize(system);
  const Index m = system.interaction_count();
  for (VectorXd* buffer : {&gaps_, &rates_, &gaps_next_, &rates_next_}) buffer->setZero(m);
  velocity_resolution_.setZero(m);
  ode_.reset();
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

  if (free_flight_) {
    Event event;
    const bool found = search(time_, target, event);
    state_at(found ? event.time : target, q_, v_);
    time_ = found ? event.time : target;
    if (found) {
      process_event(event, report);
    } else {
      system_->scatter_state(q_, v_);
    }
    report.time = time_;
    return report;
  }

  if (!ode_ || !ode_->started) restart_motion();
  auto rhs = [this](const Ode::State& y, Ode::State& dydt, double t) {
    const Index n = system_->dof();
    ode_->q = Eigen::Map<const VectorXd>(y.data(), n);
    ode_->v = Eigen::Map<const VectorXd>(y.data() + n, n);
    const std::vector<Index>& persistent = system_->index_sets().persistent;
    dynamics_.evaluate(t, ode_->q, ode_->v, persistent);
    if (persistent.empty()) {
      ode_->a = dynamics_.free_acceleration();
    } else {
      dynamics_.acceleration(dynamics_.bilateral_force(), ode_->a);
    }
    Eigen::Map<VectorXd>(dydt.data(), n) = ode_->v;
    Eigen::Map<VectorXd>(dydt.data() + n, n) = ode_->a;
  };
  while (true) {
    if (ode_->dense.current_time() <= time_) {
      const auto [from, to] = ode_->dense.do_step(rhs);
      ode_->last_step = to - from;
      ++report.smooth_steps;
      continue;
    }
    const double end = std::min(ode_->dense.current_time(), target);
    Event event;
    if (search(time_, end, event)) {
      state_at(event.time, q_, v_);
      time_ = event.time;
      process_event(event, report);
      return report;
    }
    state_at(end, q_, v_);
    time_ = end;
    if (end >= target) {
      system_->scatter_state(q_, v_);
      report.time = time_;
      return report;
    }
  }
}

void EventDrivenIntegrator::restart_motion() {
  if (!ode_) ode_ = std::make_unique<Ode>(options_);
  const Index n = system_->dof();
  ode_->y.resize(2 * n);
  ode_->probe.resize(2 * n);
  Eigen::Map<VectorXd>(ode_->y.data(), n) = q_;
  Eigen::Map<VectorXd>(ode_->y.data() + n, n) = v_;
  const double first_step = ode_->last_step > 0.0 ? ode_->last_step : 1e-4;
  ode_->dense.initialize(ode_->y, time_, first_step);
  ode_->started = true;
}

void EventDrivenIntegrator::state_at(double t, VectorXd& q, VectorXd& v) {
  if (free_flight_) {
    q = q_ + (t - time_) * v_;
    v = v_;
    return;
  }
  const Index n = system_->dof();
  ode_->dense.calc_state(t, ode_->probe);
  q = Eigen::Map<const VectorXd>(ode_->probe.data(), n);
  v = Eigen::Map<const VectorXd>(ode_->probe.data() + n, n);
}

void EventDrivenIntegrator::watch(double t, const VectorXd& q, const VectorXd& v, VectorXd& gaps,
                                  VectorXd& rates, VectorXd& forces) {
  const std::vector<Index>& persistent = system_->index_sets().persistent;
  for (Index j = 0; j < system_->interaction_count(); ++j) {
    gaps(j) = system_->gap(j, q);
    rates(j) = system_->velocity(j, q, v);
  }
  if (persistent.empty()) return;
  if (free_flight_) {  // no force, constant W: nothing presses a persistent contact
    forces.setZero(Index(persistent.size()));
    return;
  }
  dynamics_.evaluate(t, q, v, persistent);
  forces = dynamics_.bilateral_force();
}

double EventDrivenIntegrator::gap_function(Index j, double t) {
  state_at(t, q_probe_, v_probe_);
  return system_->gap(j, q_probe_);
}

double EventDrivenIntegrator::rate_function(Index j, double t) {
  state_at(t, q_probe_, v_probe_);
  return system_->velocity(j, q_probe_, v_probe_);
}

double EventDrivenIntegrator::force_function(Index k, double t) {
  state_at(t, q_probe_, v_probe_);
  dynamics_.evaluate(t, q_probe_, v_probe_, system_->index_sets().persistent);
  return dynamics_.bilateral_force()(k);
}

double EventDrivenIntegrator::closing_time(Index j, double t0, double t1, double& level) {
  const double tolerance = options_.event_tolerance;
  const double g0 = gaps_(j), g1 = gaps_next_(j), u0 = rates_(j), u1 = rates_next_(j);
  // between two samples the gap has at most one turn, found where its rate u changes sign
  auto turn = [&](double sign) {  // the time of the turn: u crosses 0 from sign*u > 0
    return numerics::narrow_crossing([&](double s) { return sign * rate_function(j, s); }, t0,
                                     t1, sign * u0, sign * u1, tolerance)
        .upper;
  };
  auto crossing = [&](double lower, double upper, double f_lower, double f_upper) {
    return numerics::narrow_crossing([&](double s) { return gap_function(j, s) - level; },
                                     lower, upper, f_lower, f_upper, tolerance)
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
  const std::vector<Index>& persistent = system_->index_sets().persistent;
  std::vector<char> held(std::size_t(system_->interaction_count()), 0);
  for (Index j : persistent) held[std::size_t(j)] = 1;
  const double tolerance = options_.event_tolerance;
  state_at(a, q_probe_, v_probe_);
  watch(a, q_probe_, v_probe_, gaps_, rates_, forces_probe_);
  // an open contact closes when its gap reaches 0; one that starts closed (and is not held)
  // when it sinks a gap tolerance below where it starts, or reaches 0 again after opening
  levels_.resize(gaps_.size());
  for (Index j = 0; j < gaps_.size(); ++j)
    levels_(j) = gaps_(j) > 0.0 ? 0.0 : gaps_(j) - std::max(options_.gap_tolerance, 1e-300);
  double t_previous = a;
  for (int k = 1; k <= options_.samples_per_step; ++k) {
    const double t = k == options_.samples_per_step
                         ? b
                         : a + (b - a) * double(k) / double(options_.samples_per_step);
    state_at(t, q_probe_, v_probe_);
    watch(t, q_probe_, v_probe_, gaps_next_, rates_next_, forces_next_);

    struct Root {
      Index index;
      bool detaching;
      double time;
    };
    std::vector<Root> roots;
    for (Index j = 0; j < system_->interaction_count(); ++j) {
      if (held[std::size_t(j)]) continue;
      const double closing = closing_time(j, t_previous, t, levels_(j));
      if (closing < std::numeric_limits<double>::infinity()) roots.push_back({j, false, closing});
    }
    for (std::size_t p = 0; p < persistent.size(); ++p) {
      const Index k_p = Index(p);
      if (!(forces_probe_(k_p) > 0.0 && forces_next_(k_p) <= 0.0)) continue;
      const numerics::Bracket crossing = numerics::narrow_crossing(
          [&](double s) { return force_function(k_p, s); }, t_previous, t, forces_probe_(k_p),
          forces_next_(k_p), tolerance);
      roots.push_back({persistent[p], true, crossing.upper});
    }
    if (!roots.empty()) {
      double earliest = roots.front().time;
      for (const Root& root : roots) earliest = std::min(earliest, root.time);
      event = {earliest, {}, {}};
      for (const Root& root : roots)
        if (root.time <= earliest + tolerance)
          (root.detaching ? event.detaching : event.closing).push_back(root.index);
      return true;
    }
    std::swap(gaps_, gaps_next_);
    std::swap(rates_, rates_next_);
    std::swap(forces_probe_, forces_next_);
    t_previous = t;
  }
  return false;
}

void EventDrivenIntegrator::check_event_loop(double t) {
  if (t - last_event_time_ <= options_.event_tolerance) {
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
    system_->gather_state(q_, v_);
    if (solved.velocity_resolution.size() == Index(closed_.size()))
      for (std::size_t k = 0; k < closed_.size(); ++k)
        velocity_resolution_(closed_[k]) = solved.velocity_resolution(Index(k));
    report.impact = std::move(solved);
  }
  settle_pending_ = true;
  if (ode_) ode_->started = false;
}

void EventDrivenIntegrator::settle(kernel::StepReport& report) {
  // Contacts come to rest when |u| is within what the last impact resolves or their next
  // flight would be too short; the least-energy velocity change then sets their u to 0.
  // That change moves the other closed contacts too, so the classification repeats until
  // nothing changes; a contact sent into a real approach makes an impact now.
  // Events are placed just after a crossing, so closed contacts penetrate a little, and a
  // contact that closes again while already closed sinks deeper each time: the least
  // mass-weighted shift of positions, dq = M^-1 W lambda with H lambda = -g over the
  // penetrating contacts, brings them back to g = 0. Shifting one may press a neighbour in:
  // the set grows until no closed contact penetrates.
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
    for (std::size_t k = 0; k < penetrating.size(); ++k) g(Index(k)) = system_->gap(penetrating[k], q_);
    dynamics_.evaluate(time_, q_, v_, penetrating);
    const VectorXd shift = dynamics_.solve(-g);
    q_ += dynamics_.mobility() * shift;
  }

  std::vector<Index> resting;
  std::vector<char> rests(std::size_t(system_->interaction_count()), 0);
  for (std::size_t round = 0; round <= closed_.size(); ++round) {
    dynamics_.evaluate(time_, q_, v_, {});
    const VectorXd& free_acceleration = dynamics_.free_acceleration();
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
        system_->scatter_state(q_, v_);
        return;
      }
      double b = system_->jacobian_rate(j, q_, v_);
      system_->for_each_jacobian_entry(j, q_, [&](Index i, double w) { b += w * free_acceleration(i); });
      const double rest_speed = b < 0.0 ? 0.5 * -b * options_.rest_flight_time : 0.0;
      if (u <= std::max(options_.velocity_tolerance, rest_speed)) {
        resting.push_back(j);
        rests[std::size_t(j)] = 1;
        added = true;
      }
    }
    if (!added) break;
    VectorXd u(Index(resting.size()));
    for (std::size_t k = 0; k < resting.size(); ++k) u(Index(k)) = system_->velocity(resting[k], q_, v_);
    if (u.cwiseAbs().maxCoeff() > 0.0) {
      dynamics_.evaluate(time_, q_, v_, resting);
      const VectorXd impulse = dynamics_.solve(-u);
      v_ += dynamics_.mobility() * impulse;
    }
  }

  // which resting contacts stay closed: the acceleration-level LCP
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
  if (ode_) ode_->started = false;
}

kernel::ContactForces EventDrivenIntegrator::persistent_forces() {
  kernel::ContactForces forces;
  const std::vector<Index>& persistent = system_->index_sets().persistent;
  forces.time = time_;
  forces.interactions = persistent;
  forces.solved = true;
  if (persistent.empty()) return forces;
  dynamics_.evaluate(time_, q_, v_, persistent);
  forces.force = dynamics_.bilateral_force();
  forces.acceleration = VectorXd::Zero(forces.force.size());
  return forces;
}

}  // namespace mimpact::plugins
