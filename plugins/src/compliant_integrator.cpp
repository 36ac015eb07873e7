#include "mimpact/plugins/compliant_integrator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "compliant_state.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/numerics/dense_output.hpp"
#include "mimpact/numerics/event_scan.hpp"
#include "mimpact/numerics/root_bracketing.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::plugins {

using kernel::Index;
using kernel::MatrixXd;
using kernel::VectorXd;
using numerics::Crossing;

using compliant::Body;
using compliant::Contact;
using compliant::GapSamples;
using compliant::JacobianEntry;
using compliant::kNever;
using compliant::linear_gap;
using numerics::ContactEvent;

compliant::State::State(const numerics::OdeOptions& options)
    : dense(std::make_unique<numerics::DenseOutput>(options)) {}
compliant::State::~State() = default;

CompliantIntegrator::CompliantIntegrator(CompliantOptions options) : options_(options) {
  validate(options_, "compliant integrator");
}

CompliantIntegrator::~CompliantIntegrator() = default;

Index CompliantIntegrator::bodies_in_motion() const { return Index(state_->motion.moving.size()); }
Index CompliantIntegrator::most_bodies_in_motion() const { return state_->motion.most_moving; }

namespace {

// Units in the last place of the largest coordinate of a contact's bodies within which a gap
// computed from their positions is round-off.
constexpr double kGapRoundOff = 4.0;

// The round-off of contact j's gap at positions q (m).
double gap_round_off(const kernel::NonSmoothDynamicalSystem& system, const VectorXd& q, Index j) {
  double largest = 0.0;
  for (Index k : {system.first_system(j), system.second_system(j)})
    if (k >= 0)
      largest = std::max(
          largest, q.segment(system.offset(k), system.system(k).dimension()).cwiseAbs().maxCoeff());
  return kGapRoundOff * std::numeric_limits<double>::epsilon() * largest;
}

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
  s.scratch.q_all = s.anchor_q;
  s.scratch.v_all = s.anchor_v;

  s.bodies.resize(std::size_t(system.system_count()));
  s.body_of_coordinate.resize(std::size_t(system.dof()));
  s.local_of_coordinate = s.body_of_coordinate;
  for (Index k = 0; k < system.system_count(); ++k) {
    const kernel::DynamicalSystem& ds = system.system(k);
    Body& b = s.body(k);
    b.describe(system, k);
    b.has_force = ds.has_force();
    b.can_fly = s.linear && !b.has_force && b.constant;
    b.anchor_time = start;
    for (Index i = 0; i < b.size; ++i) {
      s.body_of_coordinate[std::size_t(b.offset + i)] = k;
      s.local_of_coordinate[std::size_t(b.offset + i)] = i;
    }
  }
  s.contacts.resize(std::size_t(m));
  s.motion.watch_stamp.assign(std::size_t(m), 0);
  s.scratch.gap_now.assign(std::size_t(m), 0.0);
  max_compression_.assign(std::size_t(m), 0.0);
  history_.force.setZero(m);
  history_.max_force = history_.time_of_max_force = history_.impulse = history_.force;
  history_.work = history_.stored_energy = history_.force;
  history_.work_of_forces = 0.0;
  for (Index j = 0; j < m; ++j) {
    Contact& c = s.contact(j);
    // a gap within the round-off of the positions it is computed from is a touch: a chain
    // placed end to end starts touching at every contact, however far from the origin
    // (docs/design/compliant_contacts.md)
    c.anchor_gap = system.gap(j, s.anchor_q);
    if (std::abs(c.anchor_gap) <= gap_round_off(system, s.anchor_q, j)) c.anchor_gap = 0.0;
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
  prepare_friction();
  restart();
  update_stored_energy();
  history_.stored_energy_at_start = history_.stored_energy;
  history_.all_open = contacts_open();
}

// The integration restarted on the moving set as it is now: slots, the watched contacts, the
// state y = (displacements, velocities, impulses since now).
void CompliantIntegrator::restart() {
  State& s = *state_;
  std::sort(s.motion.moving.begin(), s.motion.moving.end());
  s.motion.coordinates = 0;
  for (Index k : s.motion.moving) {
    s.body(k).slot = s.motion.coordinates;
    s.motion.coordinates += s.body(k).size;
  }
  s.motion.most_moving = std::max(s.motion.most_moving, Index(s.motion.moving.size()));
  for (std::size_t a = 0; a < s.motion.joined.size(); ++a)
    s.contact(s.motion.joined[a]).slot = Index(a);
  // y = (displacements, velocities, impulses since now)
  s.y.assign(2 * std::size_t(s.motion.coordinates) + s.motion.joined.size(), 0.0);
  for (Index k : s.motion.moving) {
    const Body& b = s.body(k);
    for (Index i = 0; i < b.size; ++i)
      s.y[std::size_t(s.motion.coordinates + b.slot + i)] = s.anchor_v(b.offset + i);
  }
  // the contacts the integrated bodies touch
  ++s.motion.stamp;
  s.motion.watched.clear();
  for (Index k : s.motion.moving)
    for (Index j : system_->interactions_of(k))
      if (s.motion.watch_stamp[std::size_t(j)] != s.motion.stamp) {
        s.motion.watch_stamp[std::size_t(j)] = s.motion.stamp;
        s.motion.watched.push_back(j);
      }
  for (GapSamples* samples : {&s.scratch.before, &s.scratch.after}) {
    samples->gap.resize(s.motion.watched.size());
    samples->rate.resize(s.motion.watched.size());
  }
  s.scratch.generalized.resize(s.motion.coordinates);
  if (s.friction.on) restart_friction();
  s.probe = s.y;
  start_accounting();
  // after an event, the step the integration last took
  s.dense->restart(s.y, time_, s.dense->last_step() > 0.0 ? s.dense->last_step() : 1e-7);
}

kernel::StepReport CompliantIntegrator::advance(double target) {
  State& s = *state_;
  kernel::StepReport report;
  report.time = time_;
  if (target <= time_) return report;
  bool reached = false;
  while (true) {
    if (s.motion.moving.empty()) {  // every body in free flight: up to the next computed join
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
    if (s.dense->time() <= time_) {
      take_step();
      ++report.smooth_steps;
      continue;
    }
    const double end_of_step = std::min(s.dense->time(), target);
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
  s.dense->step([this](const numerics::DenseOutput::State& y, numerics::DenseOutput::State& dydt,
                       double t) { evaluate(t, y.data(), dydt.data()); });
  const double t = s.dense->time();
  if (s.dense->steps() > options_.max_steps) {
    // beads that keep almost nothing of their approach stay in contact at nearly zero force and
    // touch again and again: the usual cause, which the message names
    const bool plastic =
        std::any_of(laws_.begin(), laws_.end(),
                    [](const numerics::ContactLaw& law) { return law.restitution < 0.01; });
    throw BudgetSpent(
        "compliant integrator: max_steps = " + std::to_string(options_.max_steps) +
            " time steps taken by t = " + to_text(t) + " s (compliant.max_steps in a scene); " +
            (plastic ? "with restitution below 0.01 the beads stay touching at nearly zero "
                       "force and collide again and again (the LZB method treats e -> 0 exactly)"
                     : "a long run needs a larger compliant.max_steps or a looser tolerance; "
                       "where the steps are tiny, the contacts' time scale is below what the "
                       "tolerance and double precision resolve (check the speeds and "
                       "stiffnesses)"),
        t);
  }
  const numerics::DenseOutput::State& now = s.dense->state();
  if (!std::all_of(now.begin(), now.end(), [](double x) { return std::isfinite(x); }))
    throw Error("compliant integrator: the state is not finite at t = " + to_text(t) +
                " s; speeds, forces or stiffnesses are out of the range double precision carries");
}

// Gaps and rates of `contacts` at time t of the current step.
void CompliantIntegrator::measure(double t, std::span<const Index> contacts,
                                  std::vector<double>& gap, std::vector<double>& rate) {
  State& s = *state_;
  s.dense->state_at(t, s.probe);
  if (!s.linear) {
    for (Index k : s.motion.moving) {
      const Body& body = s.body(k);
      for (Index i = 0; i < body.size; ++i) {
        s.scratch.q_all(body.offset + i) = s.anchor_q(body.offset + i) + s.probe[body.slot + i];
        s.scratch.v_all(body.offset + i) = s.probe[s.motion.coordinates + body.slot + i];
      }
    }
  }
  for (std::size_t w = 0; w < contacts.size(); ++w) {
    const Index j = contacts[w];
    if (s.linear) {
      linear_gap(s, s.contact(j), t, s.probe.data(), gap[w], rate[w]);
    } else {
      gap[w] = system_->gap(j, s.scratch.q_all);
      rate[w] = system_->velocity(j, s.scratch.q_all, s.scratch.v_all);
    }
  }
}

bool CompliantIntegrator::next_event(double a, double b, Event& event) {
  State& s = *state_;
  const numerics::Overlaps overlaps{.join = s.join_overlap, .leave = s.leave_overlap};
  const bool rubbing = !s.friction.rubbing.empty();
  auto watch = [&](double t, GapSamples& samples) {
    measure(t, s.motion.watched, samples.gap, samples.rate);
    if (rubbing) watch_friction(t, samples.friction);
  };
  s.scratch.event_gap.resize(1);
  s.scratch.event_rate.resize(1);
  // each watched contact's event over [t0, t1] (numerics::classify), located to the event
  // tolerance
  auto locate = [&](double t0, double t1, const GapSamples& before, const GapSamples& after,
                    std::vector<Crossing>& found) {
    for (std::size_t w = 0; w < s.motion.watched.size(); ++w) {
      const Index j = s.motion.watched[w];
      numerics::ContactWatch watched;
      watched.joined = s.contact(j).joined;
      watched.may_freeze = options_.frozen_gaps && s.contact(j).has_closed;
      watched.gap_before = before.gap[w];
      watched.gap_after = after.gap[w];
      watched.rate_before = before.rate[w];
      watched.rate_after = after.rate[w];
      const numerics::Classified crossed = numerics::classify(watched, overlaps);
      if (crossed.kind == ContactEvent::none) continue;
      if (crossed.at_start) {
        found.push_back({long(j), int(crossed.kind), t0});
        continue;
      }
      auto value = [&](double gap, double rate) {
        return numerics::event_function(crossed.kind, gap, rate, overlaps);
      };
      const Index one[] = {j};
      const numerics::Bracket bracket = numerics::narrow_crossing(
          [&](double t) {
            measure(t, one, s.scratch.event_gap, s.scratch.event_rate);
            return value(s.scratch.event_gap[0], s.scratch.event_rate[0]);
          },
          t0, t1, value(watched.gap_before, watched.rate_before),
          value(watched.gap_after, watched.rate_after), options_.ode.event_tolerance);
      // the event just handled, seen again through round-off of the restarted state; another
      // contact crossing at the same time (a symmetric strike loads two contacts at once) is
      // an event of its own
      if (j == s.motion.last_event && bracket.upper <= a + options_.ode.event_tolerance) continue;
      found.push_back({long(j), int(crossed.kind), bracket.upper});
    }
    if (rubbing) locate_switches(t0, t1, before.friction, after.friction, found);
  };
  const std::vector<Crossing> found =
      numerics::scan_events({.start = a,
                             .end = b,
                             .samples = options_.ode.samples_per_step,
                             .tolerance = options_.ode.event_tolerance},
                            s.scratch.before, s.scratch.after, watch, locate);
  double earliest = kNever;
  for (const Crossing& crossing : found)
    if (crossing.time < earliest) {
      earliest = crossing.time;
      const int coulomb = coulomb_switch(crossing.kind);
      event = {Index(crossing.index),
               coulomb >= 0 ? ContactEvent::none : ContactEvent(crossing.kind), crossing.time,
               coulomb};
    }
  return next_predicted_join(a, std::min(b, earliest), event) || earliest != kNever;
}

void CompliantIntegrator::end_segment(double end) {
  State& s = *state_;
  s.dense->state_at(end, s.y);
  time_ = end;
  account_work(end);
  for (Index j : s.motion.joined) {
    // a contact's force peaks where it turns, and a located turn ends a segment
    double gap, rate;
    if (s.linear) {
      linear_gap(s, s.contact(j), time_, s.y.data(), gap, rate);
    } else {
      for (Index k : s.motion.moving) {
        const Body& body = s.body(k);
        for (Index i = 0; i < body.size; ++i)
          s.scratch.q_all(body.offset + i) = s.anchor_q(body.offset + i) + s.y[body.slot + i];
      }
      gap = system_->gap(j, s.scratch.q_all);
    }
    s.scratch.gap_now[std::size_t(j)] = gap;
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
  if (event.coulomb >= 0) {  // the contact's phase switches: the integration restarts there
    pass_switch(event);
    commit_motion();
    restart();
    return false;
  }
  s.motion.last_event = event.contact;
  const std::size_t i = std::size_t(event.contact);
  if (event.kind == ContactEvent::turning) {
    // e < 1 unloads along another curve from here; for e = 1 the restart keeps the step
    // from stepping over the peak (the separation speed to 1e-9 at the default tolerances)
    commit_motion();
    max_compression_[i] = std::max(max_compression_[i], -s.scratch.gap_now[i]);
    restart();
    return false;
  }
  if (event.kind == ContactEvent::reanchoring) {
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
  if (event.kind == ContactEvent::joining) {
    if (s.contact(event.contact).predicted) {  // the computed join is used up
      s.motion.predictions.pop();
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
  (event.kind == ContactEvent::joining ? report.closing : report.detaching)
      .push_back(event.contact);
  return true;
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
  const Index n = s.motion.coordinates;
  if (reached_target) {
    for (Index k = 0; k < Index(s.bodies.size()); ++k) write_back(k);
  } else {
    for (Index k : s.motion.moving) write_back(k);
  }
  for (Index j : s.motion.joined)
    history_.impulse(j) = s.contact(j).impulse + s.y[std::size_t(2 * n + s.contact(j).slot)];
  for (Index j : s.friction.rubbing) {
    const compliant::Rub& rub = s.contact(j).rub;
    for (int k = 0; k < rub.rows; ++k)
      history_.tangential_impulse(j, k) =
          rub.impulse[std::size_t(k)] + s.y[std::size_t(rub.slot + k)];
  }
  update_stored_energy();
  history_.all_open = contacts_open();
}

bool CompliantIntegrator::contacts_open() {
  State& s = *state_;
  if (!s.motion.joined.empty() || s.motion.pending_predictions > 0) return false;
  // the integrated bodies' contacts: none touching, none approaching
  if (s.motion.watched.empty()) return true;
  s.scratch.event_gap.resize(s.motion.watched.size());
  s.scratch.event_rate.resize(s.motion.watched.size());
  for (std::size_t w = 0; w < s.motion.watched.size(); ++w) {
    const Index j = s.motion.watched[w];
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
