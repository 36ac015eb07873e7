#include "mimpact/plugins/compliant_integrator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>

#include "mimpact/common/error.hpp"
#include "mimpact/numerics/internal/dense_output.hpp"
#include "mimpact/numerics/internal/event_scan.hpp"
#include "mimpact/numerics/internal/root_bracketing.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::plugins {

using kernel::Index;
using kernel::MatrixXd;
using kernel::VectorXd;
using numerics::internal::Crossing;

namespace {

// What ends a segment of the integration at a contact.
// turning: a joined contact's compression ends; reanchoring: an open contact stops separating
// (frozen gaps only)
enum class EventKind { none, joining, leaving, turning, reanchoring };

constexpr double kNever = std::numeric_limits<double>::infinity();

// A body of the system: its block of coordinates and how it moves now. Out of the motion it
// flies freely, q(t) = anchor_q + anchor_v (t - anchor_time); in it, its displacement from
// anchor_q and its velocity are part of the integrated state, from slot on.
struct Body {
  Index offset = 0, size = 0;  // in the system's global coordinates
  bool can_fly = false;        // no force, a constant mass, only linear relations
  bool has_force = false, constant_mass = true, diagonal = true, factorized = false;
  VectorXd inverse_diagonal;
  Eigen::LLT<MatrixXd> cholesky;
  MatrixXd mass;
  mutable VectorXd q, v;  // workspaces of the right-hand side and of write_back
  VectorXd force;
  bool in_motion = false;
  Index slot = -1;
  double anchor_time = 0.0;
  int loaded_contacts = 0;  // joined contacts touching it
};

// W_j entry of a linear relation: coordinate `local` of `body`.
struct JacobianEntry {
  Index body = 0, local = 0;
  double value = 0.0;
};

struct Contact {
  std::vector<JacobianEntry> entries;  // linear relations: constant
  double anchor_gap = 0.0;             // linear relations: the gap at the bodies' anchors (m)
  bool joined = false;
  // closed at the start or joined since: a gap it has opened since may be frozen
  bool has_closed = false;
  Index slot = -1;       // of its impulse in the integrated state
  double impulse = 0.0;  // N s, until the last commit
  // where its work was last accounted: the impulse since the last restart (N s) and u (m/s)
  double accounted_impulse = 0.0, accounted_rate = 0.0;
  std::uint32_t version = 0;  // invalidates its pending join prediction
  bool predicted = false;
};

// A join computed in closed form, between bodies in free flight.
struct PredictedJoin {
  double time;
  Index contact;
  std::uint32_t version;
  bool operator>(const PredictedJoin& other) const { return time > other.time; }
};

// Gaps (m) and rates (m/s) of the watched contacts at one time.
struct GapSamples {
  std::vector<double> gap, rate;
};

}  // namespace

struct CompliantIntegrator::State {
  explicit State(const numerics::OdeOptions& options) : dense(options) {}

  numerics::internal::DenseOutput dense;
  numerics::internal::DenseOutput::State y, probe;
  bool linear = true;
  double join_overlap = 0.0, leave_overlap = 0.0;  // m
  std::vector<Body> bodies;
  std::vector<Contact> contacts;
  VectorXd anchor_q, anchor_v;  // global coordinates
  std::vector<Index> body_of_coordinate, local_of_coordinate;
  // the motion: its bodies, its joined contacts, the contacts watched for events
  std::vector<Index> moving, joined, watched;
  Index moving_coordinates = 0, most_moving = 0;
  std::vector<std::uint32_t> watch_stamp;
  std::uint32_t stamp = 0;
  std::priority_queue<PredictedJoin, std::vector<PredictedJoin>, std::greater<>> predictions;
  Index pending_predictions = 0;
  // the contact of the event handled last: its crossing, seen again at the start of the next
  // segment through round-off of the restarted state, is not an event
  Index last_event = -1;
  // right-hand side workspace
  VectorXd generalized;
  VectorXd q_all, v_all;  // nonlinear relations: every coordinate
  GapSamples before, after;
  std::vector<double> event_gap, event_rate;
  std::vector<double> gap_now;  // m, of the joined contacts at the end of the last segment
  // the moving coordinates' velocities and the time where the forces' work was last accounted
  std::vector<double> accounted_velocity;
  double accounted_time = 0.0;

  Body& body(Index k) { return bodies[std::size_t(k)]; }
  Contact& contact(Index j) { return contacts[std::size_t(j)]; }

  // displacement from the anchor and velocity of coordinate `local` of body k at time t, with
  // the integrated state y
  double displacement(const Body& b, Index local, double t, const double* state) const {
    return b.in_motion ? state[b.slot + local] : anchor_v(b.offset + local) * (t - b.anchor_time);
  }
  double velocity(const Body& b, Index local, const double* state) const {
    return b.in_motion ? state[moving_coordinates + b.slot + local] : anchor_v(b.offset + local);
  }
};

struct CompliantIntegrator::Event {
  Index contact = -1;
  EventKind kind = EventKind::none;
  double time = 0.0;
};

CompliantIntegrator::CompliantIntegrator(CompliantOptions options) : options_(options) {
  validate(options_, "compliant integrator");
}

CompliantIntegrator::~CompliantIntegrator() = default;

Index CompliantIntegrator::bodies_in_motion() const { return Index(state_->moving.size()); }
Index CompliantIntegrator::most_bodies_in_motion() const { return state_->most_moving; }

namespace {

std::vector<numerics::ContactLaw> compliant_laws(const kernel::NonSmoothDynamicalSystem& system) {
  std::vector<numerics::ContactLaw> laws;
  for (Index j = 0; j < system.interaction_count(); ++j) {
    const auto* law = dynamic_cast<const LzbLaw*>(&system.interaction(j).law());
    if (!law)
      throw InvalidInput("interaction '" + system.interaction(j).name() + "' has a \"" +
                         std::string(system.interaction(j).law().kind()) +
                         "\" law; the compliant integrator needs its compliance: plugins::LzbLaw");
    const numerics::ContactLaw& contact = law->contact_law();
    if (contact.model == numerics::ComplianceModel::mono_stiffness && contact.restitution < 1.0)
      throw InvalidInput("interaction '" + system.interaction(j).name() +
                         "': the compliant integrator follows the bi-stiffness unloading curve "
                         "(docs/model.md, section 3); a mono-stiffness law with e < 1 has no "
                         "time-domain form here");
    laws.push_back(contact);
    laws.back().restitution = contact.effective_restitution();
  }
  return laws;
}

}  // namespace

void CompliantIntegrator::initialize(kernel::NonSmoothDynamicalSystem& system, double start,
                                     const kernel::EventProblems&) {
  system_ = &system;
  time_ = start;
  laws_ = compliant_laws(system);
  state_ = std::make_unique<State>(options_.ode);
  State& s = *state_;
  const Index m = system.interaction_count();
  for (Index j = 0; j < m; ++j) s.linear = s.linear && system.interaction(j).relation().is_linear();
  s.join_overlap = options_.overlap_resolution;
  s.leave_overlap = 0.5 * s.join_overlap;
  system.gather_state(s.anchor_q, s.anchor_v);
  s.q_all = s.anchor_q;
  s.v_all = s.anchor_v;

  s.bodies.resize(std::size_t(system.system_count()));
  s.body_of_coordinate.resize(std::size_t(system.dof()));
  s.local_of_coordinate = s.body_of_coordinate;
  for (Index k = 0; k < system.system_count(); ++k) {
    const kernel::DynamicalSystem& ds = system.system(k);
    Body& b = s.body(k);
    b.offset = system.offset(k);
    b.size = ds.dimension();
    b.has_force = ds.has_force();
    b.constant_mass = ds.mass_is_constant();
    b.diagonal = ds.mass_is_diagonal();
    b.can_fly = s.linear && !b.has_force && b.constant_mass;
    b.mass.setZero(b.size, b.size);
    b.q.setZero(b.size);
    b.v = b.force = b.q;
    b.anchor_time = start;
    for (Index i = 0; i < b.size; ++i) {
      s.body_of_coordinate[std::size_t(b.offset + i)] = k;
      s.local_of_coordinate[std::size_t(b.offset + i)] = i;
    }
  }
  s.contacts.resize(std::size_t(m));
  s.watch_stamp.assign(std::size_t(m), 0);
  s.gap_now.assign(std::size_t(m), 0.0);
  max_compression_.assign(std::size_t(m), 0.0);
  history_.force.setZero(m);
  history_.max_force = history_.time_of_max_force = history_.impulse = history_.force;
  history_.work = history_.stored_energy = history_.force;
  history_.work_of_forces = 0.0;
  for (Index j = 0; j < m; ++j) {
    Contact& c = s.contact(j);
    c.anchor_gap = system.gap(j, s.anchor_q);
    c.has_closed = c.anchor_gap <= s.leave_overlap;  // touching at the start
    if (s.linear)
      system.for_each_jacobian_entry(j, s.anchor_q, [&](Index coordinate, double value) {
        if (value != 0.0)
          c.entries.push_back({s.body_of_coordinate[std::size_t(coordinate)],
                               s.local_of_coordinate[std::size_t(coordinate)], value});
      });
  }
  // a contact that starts compressed (a static load) starts on its loading curve
  for (Index j = 0; j < m; ++j)
    if (-s.contact(j).anchor_gap > s.join_overlap) {
      join(j);
      max_compression_[std::size_t(j)] = -s.contact(j).anchor_gap;
      history_.force(j) = history_.max_force(j) =
          contact_force(std::size_t(j), -s.contact(j).anchor_gap);
    }
  for (Index k = 0; k < system.system_count(); ++k)
    if (!s.body(k).can_fly) set_in_motion(k);
  for (Index j = 0; j < m; ++j) predict_join(j);
  slow_speed_ = options_.ode.relative_tolerance * s.anchor_v.cwiseAbs().maxCoeff();
  restart();
  update_stored_energy();
  history_.stored_energy_at_start = history_.stored_energy;
  history_.all_open = contacts_open();
}

double CompliantIntegrator::contact_energy(std::size_t j, double delta) const {
  if (!(delta > 0.0)) return 0.0;
  const numerics::ContactLaw& law = laws_[j];
  const double delta_max = max_compression_[j];
  if (delta >= delta_max || law.restitution >= 1.0)
    return law.force(delta) * delta / (1.0 + law.exponent);
  // the unloading curve from delta_max, which reaches 0 at delta_r (contact_force)
  const double delta_r = delta_max * (1.0 - law.restitution * law.restitution);
  if (delta <= delta_r) return 0.0;
  return contact_force(j, delta) * (delta - delta_r) / (1.0 + law.exponent);
}

double CompliantIntegrator::contact_force(std::size_t j, double delta) const {
  if (!(delta > 0.0)) return 0.0;
  const numerics::ContactLaw& law = laws_[j];
  const double delta_max = max_compression_[j];
  if (delta >= delta_max || law.restitution >= 1.0) return law.force(delta);
  const double e = law.restitution;
  const double delta_r = delta_max * (1.0 - e * e);
  if (delta <= delta_r) return 0.0;
  return law.force(delta_max) *
         numerics::power_law((delta - delta_r) / (delta_max - delta_r), law.exponent);
}

// ---- who takes part ----------------------------------------------------------------------

void CompliantIntegrator::commit_motion() {
  State& s = *state_;
  for (Index k : s.moving) {
    Body& b = s.body(k);
    for (Index i = 0; i < b.size; ++i) {
      const double d = s.y[std::size_t(b.slot + i)];
      s.anchor_q(b.offset + i) += d;
      s.anchor_v(b.offset + i) = s.y[std::size_t(s.moving_coordinates + b.slot + i)];
      if (!s.linear || d == 0.0) continue;
      for (Index j : system_->interactions_of(k))
        for (const JacobianEntry& entry : s.contact(j).entries)
          if (entry.body == k && entry.local == i) s.contact(j).anchor_gap += entry.value * d;
    }
    b.anchor_time = time_;
  }
  const std::size_t impulses = 2 * std::size_t(s.moving_coordinates);
  for (Index j : s.joined) {
    Contact& c = s.contact(j);
    c.impulse += s.y[impulses + std::size_t(c.slot)];
    history_.impulse(j) = c.impulse;
  }
}

void CompliantIntegrator::set_in_motion(Index k) {
  State& s = *state_;
  Body& b = s.body(k);
  if (b.in_motion) return;
  fold_flight(k);
  b.in_motion = true;
  s.moving.push_back(k);
  for (Index j : system_->interactions_of(k)) forget_prediction(j);
}

// A body in free flight: its flight up to now folded into its anchor.
void CompliantIntegrator::fold_flight(Index k) {
  State& s = *state_;
  Body& b = s.body(k);
  if (b.in_motion) return;  // anchored by the last commit
  for (Index i = 0; i < b.size; ++i) {
    const double d = s.anchor_v(b.offset + i) * (time_ - b.anchor_time);
    s.anchor_q(b.offset + i) += d;
    if (!s.linear || d == 0.0) continue;
    for (Index j : system_->interactions_of(k))
      for (const JacobianEntry& entry : s.contact(j).entries)
        if (entry.body == k && entry.local == i) s.contact(j).anchor_gap += entry.value * d;
  }
  b.anchor_time = time_;
}

void CompliantIntegrator::set_free(Index k) {
  State& s = *state_;
  Body& b = s.body(k);
  if (!b.in_motion || !b.can_fly || b.loaded_contacts > 0) return;
  b.in_motion = false;
  std::erase(s.moving, k);
  for (Index j : system_->interactions_of(k)) predict_join(j);
}

void CompliantIntegrator::join(Index j) {
  State& s = *state_;
  Contact& c = s.contact(j);
  c.joined = true;
  c.has_closed = true;
  s.joined.push_back(j);
  forget_prediction(j);
  for (Index k : {system_->first_system(j), system_->second_system(j)})
    if (k >= 0) {
      ++s.body(k).loaded_contacts;
      set_in_motion(k);
    }
}

void CompliantIntegrator::leave(Index j) {
  State& s = *state_;
  s.contact(j).joined = false;
  std::erase(s.joined, j);
  max_compression_[std::size_t(j)] = 0.0;  // the contact forgets
  history_.force(j) = 0.0;
  for (Index k : {system_->first_system(j), system_->second_system(j)})
    if (k >= 0) {
      --s.body(k).loaded_contacts;
      set_free(k);
    }
}

// Between bodies in free flight the gap is linear in time: the join is where it reaches
// -join_overlap.
void CompliantIntegrator::predict_join(Index j) {
  State& s = *state_;
  Contact& c = s.contact(j);
  if (!s.linear || c.joined || c.predicted) return;
  double gap = c.anchor_gap, rate = 0.0;
  for (const JacobianEntry& entry : c.entries) {
    const Body& b = s.body(entry.body);
    if (b.in_motion) return;  // watched along the integration instead
    const double v = s.anchor_v(b.offset + entry.local);
    gap += entry.value * v * (time_ - b.anchor_time);
    rate += entry.value * v;
  }
  if (!(rate < 0.0)) return;
  if (options_.frozen_gaps && c.has_closed && gap > s.leave_overlap) {
    c.anchor_gap -= gap;  // it approaches again (turned by a collision): its gap is forgotten
    gap = 0.0;
  }
  const double time = time_ + std::max(0.0, (gap + s.join_overlap) / -rate);
  s.predictions.push({time, j, c.version});
  c.predicted = true;
  ++s.pending_predictions;
}

void CompliantIntegrator::forget_prediction(Index j) {
  State& s = *state_;
  Contact& c = s.contact(j);
  ++c.version;
  if (!c.predicted) return;
  c.predicted = false;
  --s.pending_predictions;
}

void CompliantIntegrator::restart() {
  State& s = *state_;
  std::sort(s.moving.begin(), s.moving.end());
  s.moving_coordinates = 0;
  for (Index k : s.moving) {
    s.body(k).slot = s.moving_coordinates;
    s.moving_coordinates += s.body(k).size;
  }
  s.most_moving = std::max(s.most_moving, Index(s.moving.size()));
  for (std::size_t a = 0; a < s.joined.size(); ++a) s.contact(s.joined[a]).slot = Index(a);
  // y = (displacements, velocities, impulses since now)
  s.y.assign(2 * std::size_t(s.moving_coordinates) + s.joined.size(), 0.0);
  for (Index k : s.moving) {
    const Body& b = s.body(k);
    for (Index i = 0; i < b.size; ++i)
      s.y[std::size_t(s.moving_coordinates + b.slot + i)] = s.anchor_v(b.offset + i);
  }
  // the contacts the integrated bodies touch
  ++s.stamp;
  s.watched.clear();
  for (Index k : s.moving)
    for (Index j : system_->interactions_of(k))
      if (s.watch_stamp[std::size_t(j)] != s.stamp) {
        s.watch_stamp[std::size_t(j)] = s.stamp;
        s.watched.push_back(j);
      }
  for (GapSamples* samples : {&s.before, &s.after}) {
    samples->gap.resize(s.watched.size());
    samples->rate.resize(s.watched.size());
  }
  s.generalized.resize(s.moving_coordinates);
  s.probe = s.y;
  start_accounting();
  // after an event, the step the integration last took
  s.dense.restart(s.y, time_, s.dense.last_step() > 0.0 ? s.dense.last_step() : 1e-7);
}

// ---- the motion ----------------------------------------------------------------------------

namespace {

// Gap and rate of contact j along the integrated state y at time t.
template <class StateT>
void linear_gap(const StateT& s, const Contact& c, double t, const double* y, double& gap,
                double& rate) {
  gap = c.anchor_gap;
  rate = 0.0;
  for (const JacobianEntry& entry : c.entries) {
    const Body& b = s.bodies[std::size_t(entry.body)];
    gap += entry.value * s.displacement(b, entry.local, t, y);
    rate += entry.value * s.velocity(b, entry.local, y);
  }
}

}  // namespace

void CompliantIntegrator::evaluate(double t, const double* y, double* dydt) {
  State& s = *state_;
  const Index n = s.moving_coordinates;
  s.generalized.setZero();
  if (!s.linear) {  // every body moves: the whole configuration
    for (Index k : s.moving) {
      const Body& b = s.body(k);
      for (Index i = 0; i < b.size; ++i) {
        s.q_all(b.offset + i) = s.anchor_q(b.offset + i) + y[b.slot + i];
        s.v_all(b.offset + i) = y[n + b.slot + i];
      }
    }
  }
  for (Index j : s.joined) {
    const Contact& c = s.contact(j);
    double gap, rate;
    if (s.linear) {
      linear_gap(s, c, t, y, gap, rate);
    } else {
      gap = system_->gap(j, s.q_all);
    }
    const double f = contact_force(std::size_t(j), -gap);
    dydt[2 * n + c.slot] = f;
    if (f == 0.0) continue;
    if (s.linear) {
      for (const JacobianEntry& entry : c.entries)
        s.generalized(s.body(entry.body).slot + entry.local) += entry.value * f;
    } else {
      system_->for_each_jacobian_entry(j, s.q_all, [&](Index coordinate, double value) {
        const Body& b = s.body(s.body_of_coordinate[std::size_t(coordinate)]);
        s.generalized(b.slot + s.local_of_coordinate[std::size_t(coordinate)]) += value * f;
      });
    }
  }
  for (Index k : s.moving) {
    Body& b = s.body(k);
    b.q = s.anchor_q.segment(b.offset, b.size) + Eigen::Map<const VectorXd>(y + b.slot, b.size);
    b.v = Eigen::Map<const VectorXd>(y + n + b.slot, b.size);
    if (!b.constant_mass || !b.factorized) {
      system_->system(k).mass(b.q, b.mass);
      if (b.diagonal) {
        b.inverse_diagonal = b.mass.diagonal().cwiseInverse();
      } else {
        b.cholesky.compute(b.mass);
        if (b.cholesky.info() != Eigen::Success)
          throw Error("system '" + system_->system(k).name() +
                      "': M(q) stopped being positive definite during the motion");
      }
      b.factorized = true;
    }
    auto force = s.generalized.segment(b.slot, b.size);
    if (b.has_force) {
      system_->system(k).force(t, b.q, b.v, b.force);
      force += b.force;
    }
    Eigen::Map<VectorXd> acceleration(dydt + n + b.slot, b.size);
    if (b.diagonal) {
      acceleration = b.inverse_diagonal.cwiseProduct(force);
    } else {
      acceleration = b.cholesky.solve(force);
    }
    Eigen::Map<VectorXd>(dydt + b.slot, b.size) = b.v;
  }
}

kernel::StepReport CompliantIntegrator::advance(double target) {
  State& s = *state_;
  kernel::StepReport report;
  report.time = time_;
  if (target <= time_) return report;
  bool reached = false;
  while (true) {
    if (s.moving.empty()) {  // every body in free flight: up to the next computed join
      Event event;
      if (next_predicted_join(time_, target, event)) {
        time_ = event.time;
        if (handle_event(event, report)) break;
        continue;
      }
      time_ = target;
      reached = true;
      break;
    }
    if (s.dense.time() <= time_) {
      take_step();
      ++report.smooth_steps;
      continue;
    }
    const double end_of_step = std::min(s.dense.time(), target);
    Event event;
    const bool found = next_event(time_, end_of_step, event);
    end_segment(found ? event.time : end_of_step);
    if (found) {
      if (handle_event(event, report)) break;
      continue;
    }
    if (time_ >= target) {
      reached = true;
      break;
    }
  }
  finish_advance(reached);
  report.time = time_;
  return report;
}

void CompliantIntegrator::take_step() {
  State& s = *state_;
  s.dense.step([this](const numerics::internal::DenseOutput::State& y,
                      numerics::internal::DenseOutput::State& dydt,
                      double t) { evaluate(t, y.data(), dydt.data()); });
  const double t = s.dense.time();
  if (s.dense.steps() > options_.max_steps) {
    // beads that keep almost nothing of their approach stay in contact at nearly zero force and
    // touch again and again: the usual cause, which the message names
    const bool plastic =
        std::any_of(laws_.begin(), laws_.end(),
                    [](const numerics::ContactLaw& law) { return law.restitution < 0.01; });
    throw Error("compliant integrator: max_steps = " + std::to_string(options_.max_steps) +
                " time steps taken by t = " + to_text(t) + " s (compliant.max_steps in a scene); " +
                (plastic ? "with restitution below 0.01 the beads stay touching at nearly zero "
                           "force and collide again and again (the LZB method treats e -> 0 "
                           "exactly)"
                         : "the contacts' time scale is below what the tolerance and double "
                           "precision resolve (check the speeds and stiffnesses, or loosen the "
                           "tolerance)"));
  }
  const numerics::internal::DenseOutput::State& now = s.dense.state();
  if (!std::all_of(now.begin(), now.end(), [](double x) { return std::isfinite(x); }))
    throw Error("compliant integrator: the state is not finite at t = " + to_text(t) +
                " s; speeds, forces or stiffnesses are out of the range double precision carries");
}

bool CompliantIntegrator::next_event(double a, double b, Event& event) {
  State& s = *state_;
  // gaps and rates of the watched contacts at time t of the current step
  auto measure = [&](double t, std::span<const Index> contacts, std::vector<double>& gap,
                     std::vector<double>& rate) {
    s.dense.state_at(t, s.probe);
    if (!s.linear) {
      for (Index k : s.moving) {
        const Body& body = s.body(k);
        for (Index i = 0; i < body.size; ++i) {
          s.q_all(body.offset + i) = s.anchor_q(body.offset + i) + s.probe[body.slot + i];
          s.v_all(body.offset + i) = s.probe[s.moving_coordinates + body.slot + i];
        }
      }
    }
    for (std::size_t w = 0; w < contacts.size(); ++w) {
      const Index j = contacts[w];
      if (s.linear) {
        linear_gap(s, s.contact(j), t, s.probe.data(), gap[w], rate[w]);
      } else {
        gap[w] = system_->gap(j, s.q_all);
        rate[w] = system_->velocity(j, s.q_all, s.v_all);
      }
    }
  };
  auto watch = [&](double t, GapSamples& samples) {
    measure(t, s.watched, samples.gap, samples.rate);
  };
  // the quantity whose crossing from > 0 to <= 0 is the event
  auto signed_value = [&](EventKind kind, double gap, double rate) {
    switch (kind) {
      case EventKind::joining:
        return gap + s.join_overlap;
      case EventKind::leaving:
        return -gap - s.leave_overlap;
      case EventKind::reanchoring:
        return rate;
      default:  // turning
        return -rate;
    }
  };
  s.event_gap.resize(1);
  s.event_rate.resize(1);
  auto locate = [&](double t0, double t1, const GapSamples& before, const GapSamples& after,
                    std::vector<Crossing>& found) {
    for (std::size_t w = 0; w < s.watched.size(); ++w) {
      const Index j = s.watched[w];
      const bool joined = s.contact(j).joined;
      const double g0 = before.gap[w], g1 = after.gap[w];
      EventKind kind = EventKind::none;
      // an open contact whose gap is frozen, once it stops separating (gaps below the overlap
      // resolution are round-off of the last freeze)
      const bool freezes =
          options_.frozen_gaps && !joined && s.contact(j).has_closed && g0 > s.leave_overlap;
      if (freezes && before.rate[w] <= 0.0) {
        // it stopped separating where the segment starts (a collision turned it at once)
        found.push_back({long(j), int(EventKind::reanchoring), t0});
        continue;
      }
      // Crossed at the time of the event just handled (within its tolerance: a symmetric
      // strike moves mirror contacts alike), so already past its threshold where the segment
      // starts: it joins, or leaves, there.
      if (!joined && g0 <= -s.join_overlap && before.rate[w] < 0.0) {
        found.push_back({long(j), int(EventKind::joining), t0});
        continue;
      }
      if (joined && g0 >= -s.leave_overlap && before.rate[w] > 0.0) {
        found.push_back({long(j), int(EventKind::leaving), t0});
        continue;
      }
      if (!joined && g0 > -s.join_overlap && g1 <= -s.join_overlap) {
        kind = EventKind::joining;
      } else if (joined && g0 < -s.leave_overlap && g1 >= -s.leave_overlap) {
        kind = EventKind::leaving;
      } else if (joined && g0 < -s.leave_overlap && before.rate[w] < 0.0 && after.rate[w] >= 0.0) {
        kind = EventKind::turning;
      } else if (freezes && before.rate[w] > 0.0 && after.rate[w] <= 0.0) {
        kind = EventKind::reanchoring;
      }
      if (kind == EventKind::none) continue;
      const Index one[] = {j};
      const numerics::Bracket bracket = numerics::narrow_crossing(
          [&](double t) {
            measure(t, one, s.event_gap, s.event_rate);
            return signed_value(kind, s.event_gap[0], s.event_rate[0]);
          },
          t0, t1, signed_value(kind, g0, before.rate[w]), signed_value(kind, g1, after.rate[w]),
          options_.ode.event_tolerance);
      // the event just handled, seen again through round-off of the restarted state; another
      // contact crossing at the same time (a symmetric strike loads two contacts at once) is
      // an event of its own
      if (j == s.last_event && bracket.upper <= a + options_.ode.event_tolerance) continue;
      found.push_back({long(j), int(kind), bracket.upper});
    }
  };
  const std::vector<Crossing> found = numerics::internal::scan_events(
      a, b, options_.ode.samples_per_step, options_.ode.event_tolerance, s.before, s.after, watch,
      locate);
  double earliest = kNever;
  for (const Crossing& crossing : found)
    if (crossing.time < earliest) {
      earliest = crossing.time;
      event = {Index(crossing.index), EventKind(crossing.kind), crossing.time};
    }
  return next_predicted_join(a, std::min(b, earliest), event) || earliest != kNever;
}

bool CompliantIntegrator::next_predicted_join(double a, double b, Event& event) {
  State& s = *state_;
  while (!s.predictions.empty() &&
         s.predictions.top().version != s.contact(s.predictions.top().contact).version)
    s.predictions.pop();
  if (s.predictions.empty() || s.predictions.top().time > b) return false;
  event = {s.predictions.top().contact, EventKind::joining, std::max(a, s.predictions.top().time)};
  return true;
}

void CompliantIntegrator::end_segment(double end) {
  State& s = *state_;
  s.dense.state_at(end, s.y);
  time_ = end;
  account_work(end);
  for (Index j : s.joined) {
    // a contact's force peaks where it turns, and a located turn ends a segment
    double gap, rate;
    if (s.linear) {
      linear_gap(s, s.contact(j), time_, s.y.data(), gap, rate);
    } else {
      for (Index k : s.moving) {
        const Body& body = s.body(k);
        for (Index i = 0; i < body.size; ++i)
          s.q_all(body.offset + i) = s.anchor_q(body.offset + i) + s.y[body.slot + i];
      }
      gap = system_->gap(j, s.q_all);
    }
    s.gap_now[std::size_t(j)] = gap;
    const double f = contact_force(std::size_t(j), -gap);
    history_.force(j) = f;
    if (f > history_.max_force(j)) {
      history_.max_force(j) = f;
      history_.time_of_max_force(j) = time_;
    }
  }
}

bool CompliantIntegrator::handle_event(const Event& event, kernel::StepReport& report) {
  State& s = *state_;
  s.last_event = event.contact;
  const std::size_t i = std::size_t(event.contact);
  if (event.kind == EventKind::turning) {
    // e < 1 unloads along another curve from here; for e = 1 the restart keeps the step
    // from stepping over the peak (the separation speed to 1e-9 at the default tolerances)
    commit_motion();
    max_compression_[i] = std::max(max_compression_[i], -s.gap_now[i]);
    restart();
    return false;
  }
  if (event.kind == EventKind::reanchoring) {
    // the gap the contact opened is forgotten where it stops separating: g = 0 from here, as
    // the LZB impact, which keeps the configuration, has it
    double gap, rate;
    linear_gap(s, s.contact(event.contact), time_, s.y.data(), gap, rate);
    commit_motion();
    s.contact(event.contact).anchor_gap -= gap;
    restart();
    return false;
  }
  commit_motion();
  if (event.kind == EventKind::joining) {
    if (s.contact(event.contact).predicted) {  // the computed join is used up
      s.predictions.pop();
      forget_prediction(event.contact);
    }
    if (!collide_instantly(event.contact)) join(event.contact);
  } else {
    leave(event.contact);
  }
  restart();
  for (Index k : {system_->first_system(event.contact), system_->second_system(event.contact)})
    if (k >= 0) write_back(k);
  report.time = time_;
  report.event = true;
  (event.kind == EventKind::joining ? report.closing : report.detaching).push_back(event.contact);
  return true;
}

// Behind a wave, bodies left at rest against each other approach with speeds of the order of
// the integration's own errors. Such a collision changes the velocities by less than the
// tolerance, and its largest overlap lies below what the error control resolves, so that
// integrating it would only feed those errors (and keep ever more bodies in motion). Slower than
// relative_tolerance x the fastest initial speed, a collision is therefore taken as
// instantaneous, u+ = -e u- by the impulse P = -(1 + e) u- / H_jj, the outcome of an isolated
// pair. Linear relations and constant diagonal masses only; the ledger books its work
// -(u- + u+) P / 2, exactly what the kinetic energy loses.
bool CompliantIntegrator::collide_instantly(Index j) {
  State& s = *state_;
  Contact& c = s.contact(j);
  if (!s.linear) return false;
  double rate = 0.0, h = 0.0;
  for (const JacobianEntry& entry : c.entries) {
    Body& b = s.body(entry.body);
    if (!b.diagonal || !b.constant_mass) return false;
    if (!b.factorized) {
      system_->system(entry.body).mass(s.anchor_q.segment(b.offset, b.size), b.mass);
      b.inverse_diagonal = b.mass.diagonal().cwiseInverse();
      b.factorized = true;
    }
    rate += entry.value * s.anchor_v(b.offset + entry.local);
    h += entry.value * entry.value * b.inverse_diagonal(entry.local);
  }
  if (!(rate < 0.0 && -rate < slow_speed_)) return false;
  for (Index k : {system_->first_system(j), system_->second_system(j)})
    if (k >= 0) fold_flight(k);
  const double e = laws_[std::size_t(j)].restitution;
  const double impulse = -(1.0 + e) * rate / h;
  for (const JacobianEntry& entry : c.entries) {
    const Body& b = s.body(entry.body);
    s.anchor_v(b.offset + entry.local) += b.inverse_diagonal(entry.local) * entry.value * impulse;
  }
  c.impulse += impulse;
  history_.impulse(j) = c.impulse;
  history_.work(j) -= 0.5 * (rate - e * rate) * impulse;
  // the velocities changed: the joins of every contact of the two bodies, computed again
  for (Index k : {system_->first_system(j), system_->second_system(j)})
    if (k >= 0)
      for (Index other : system_->interactions_of(k)) {
        forget_prediction(other);
        predict_join(other);
      }
  return true;
}

// The ledger's accounting points are the segment ends: over any part of a Dormand-Prince step
// (its dense output included) the velocities change by M^-1 (W dP + dP_forces) with the same
// weights as the integrated impulses, so the trapezoidal rule on u_j and v gives the kinetic
// energy's change exactly: dT = sum_j u_j_mean dP_j + v_mean . F dt, the forces taken constant
// over the step (the precompression is). Linear relations only: W is then constant.
void CompliantIntegrator::start_accounting() {
  State& s = *state_;
  if (!s.linear) return;
  const std::size_t impulses = 2 * std::size_t(s.moving_coordinates);
  for (Index j : s.joined) {
    Contact& c = s.contact(j);
    double gap;
    linear_gap(s, c, time_, s.y.data(), gap, c.accounted_rate);
    c.accounted_impulse = s.y[impulses + std::size_t(c.slot)];
  }
  s.accounted_velocity.assign(s.y.begin() + s.moving_coordinates, s.y.begin() + impulses);
  s.accounted_time = time_;
}

void CompliantIntegrator::account_work(double t) {
  State& s = *state_;
  if (!s.linear) return;
  const Index n = s.moving_coordinates;
  for (Index j : s.joined) {
    Contact& c = s.contact(j);
    double gap, rate;
    linear_gap(s, c, t, s.y.data(), gap, rate);
    const double impulse = s.y[std::size_t(2 * n + c.slot)];
    history_.work(j) -= 0.5 * (c.accounted_rate + rate) * (impulse - c.accounted_impulse);
    c.accounted_rate = rate;
    c.accounted_impulse = impulse;
  }
  for (Index k : s.moving) {
    Body& b = s.body(k);
    if (!b.has_force) continue;
    b.q = s.anchor_q.segment(b.offset, b.size) + Eigen::Map<const VectorXd>(&s.y[b.slot], b.size);
    b.v = Eigen::Map<const VectorXd>(&s.y[n + b.slot], b.size);
    system_->system(k).force(t, b.q, b.v, b.force);
    for (Index i = 0; i < b.size; ++i) {
      double& before = s.accounted_velocity[std::size_t(b.slot + i)];
      history_.work_of_forces += 0.5 * (before + b.v(i)) * b.force(i) * (t - s.accounted_time);
      before = b.v(i);
    }
  }
  s.accounted_time = t;
}

void CompliantIntegrator::update_stored_energy() {
  State& s = *state_;
  history_.stored_energy.setZero();
  for (Index j : s.joined) {
    double gap = s.contact(j).anchor_gap, rate;
    if (s.linear) linear_gap(s, s.contact(j), time_, s.y.data(), gap, rate);
    history_.stored_energy(j) = contact_energy(std::size_t(j), -gap);
  }
}

void CompliantIntegrator::write_back(Index k) {
  State& s = *state_;
  const Body& b = s.body(k);
  b.q = s.anchor_q.segment(b.offset, b.size);
  for (Index i = 0; i < b.size; ++i) {
    b.q(i) += s.displacement(b, i, time_, s.y.data());
    b.v(i) = s.velocity(b, i, s.y.data());
  }
  system_->system(k).set_state(b.q, b.v);
}

void CompliantIntegrator::finish_advance(bool reached_target) {
  State& s = *state_;
  const Index n = s.moving_coordinates;
  if (reached_target) {
    for (Index k = 0; k < Index(s.bodies.size()); ++k) write_back(k);
  } else {
    for (Index k : s.moving) write_back(k);
  }
  for (Index j : s.joined)
    history_.impulse(j) = s.contact(j).impulse + s.y[std::size_t(2 * n + s.contact(j).slot)];
  update_stored_energy();
  history_.all_open = contacts_open();
}

bool CompliantIntegrator::contacts_open() {
  State& s = *state_;
  if (!s.joined.empty() || s.pending_predictions > 0) return false;
  // the integrated bodies' contacts: none touching, none approaching
  if (s.watched.empty()) return true;
  s.event_gap.resize(s.watched.size());
  s.event_rate.resize(s.watched.size());
  for (std::size_t w = 0; w < s.watched.size(); ++w) {
    const Index j = s.watched[w];
    double gap, rate;
    if (s.linear) {
      linear_gap(s, s.contact(j), time_, s.y.data(), gap, rate);
    } else {
      VectorXd q, v;
      system_->gather_state(q, v);
      gap = system_->gap(j, q);
      rate = system_->velocity(j, q, v);
    }
    if (gap <= 0.0 || rate < 0.0) return false;
  }
  return true;
}

}  // namespace mimpact::plugins
