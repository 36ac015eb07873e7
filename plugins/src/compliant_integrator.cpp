#include "mimpact/plugins/compliant_integrator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "contact_dynamics.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/numerics/internal/dense_output.hpp"
#include "mimpact/numerics/internal/event_scan.hpp"
#include "mimpact/numerics/internal/root_bracketing.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::plugins {

using numerics::internal::Crossing;

namespace {

// What ends a segment of the integration at a contact.
enum class EventKind { none, closing, opening, turning };

}  // namespace

// The gaps (m) and normal velocities (m/s) of every contact at one time.
struct GapSamples {
  std::vector<double> gap, rate;
};

// y = (q, v, P): positions, velocities and the impulse of every contact.
struct CompliantIntegrator::State {
  explicit State(const numerics::OdeOptions& options) : dense(options) {}

  numerics::internal::DenseOutput dense;
  numerics::internal::DenseOutput::State y, probe;
  Index n = 0, m = 0;
  bool linear = true;
  std::vector<Index> all;         // every interaction
  Eigen::SparseMatrix<double> W;  // dof x contacts, constant when every relation is linear
  VectorXd offset;                // g = W^T q + offset for linear relations
  ContactDynamics dynamics;
  VectorXd q, v, generalized, contact;  // right-hand side workspace
  GapSamples before, after, end;        // the event search's, and the segment's end
  // the round-off of each gap (m): a crossing within it is noise, not a contact event
  std::vector<double> gap_noise;
  std::vector<double> gap_probe, rate_probe;  // scratch of the root finder and the open test
};

// A contact event: which contact, what happens, when.
struct CompliantIntegrator::Event {
  Index contact = -1;
  EventKind kind = EventKind::none;
  double time = 0.0;
};

CompliantIntegrator::CompliantIntegrator(CompliantOptions options) : options_(options) {
  validate(options_, "compliant integrator");
}

CompliantIntegrator::~CompliantIntegrator() = default;

void CompliantIntegrator::initialize(kernel::NonSmoothDynamicalSystem& system, double start,
                                     const kernel::EventProblems&) {
  system_ = &system;
  time_ = start;
  state_ = std::make_unique<State>(options_.ode);
  State& s = *state_;
  s.n = system.dof();
  s.m = system.interaction_count();
  laws_.clear();
  for (Index j = 0; j < s.m; ++j) {
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
    laws_.push_back(contact);
    s.linear = s.linear && system.interaction(j).relation().is_linear();
  }
  VectorXd q, v;
  system.gather_state(q, v);
  s.all.resize(std::size_t(s.m));
  for (Index j = 0; j < s.m; ++j) s.all[std::size_t(j)] = j;
  s.W = system.jacobian_matrix(s.all, q);
  s.offset.resize(s.m);
  for (Index j = 0; j < s.m; ++j) s.offset(j) = system.gap(j, q) - s.W.col(j).dot(q);
  s.dynamics.initialize(system);
  s.y.assign(std::size_t(2 * s.n + s.m), 0.0);
  s.probe = s.y;
  std::copy(q.data(), q.data() + s.n, s.y.begin());
  std::copy(v.data(), v.data() + s.n, s.y.begin() + s.n);
  s.gap_probe.resize(std::size_t(s.m));
  s.rate_probe = s.gap_probe;
  for (GapSamples* samples : {&s.before, &s.after, &s.end})
    samples->gap = samples->rate = s.gap_probe;
  // a contact that starts compressed (a static load) starts on its loading curve
  max_compression_.assign(std::size_t(s.m), 0.0);
  history_.force.setZero(s.m);
  history_.max_force = history_.time_of_max_force = history_.impulse = history_.force;
  gaps(s.y.data(), s.y.data() + s.n, s.end.gap, s.end.rate);
  for (Index j = 0; j < s.m; ++j) {
    history_.force(j) = contact_force(std::size_t(j), -s.end.gap[std::size_t(j)]);
    history_.max_force(j) = history_.force(j);
    max_compression_[std::size_t(j)] = std::max(0.0, -s.end.gap[std::size_t(j)]);
  }
  history_.all_open = contacts_open();
}

double CompliantIntegrator::contact_force(std::size_t j, double delta) const {
  if (!(delta > 0.0)) return 0.0;
  const numerics::ContactLaw& law = laws_[j];
  const double delta_max = max_compression_[j];
  if (delta >= delta_max || law.restitution >= 1.0)
    return law.stiffness * std::pow(delta, law.exponent);
  const double e = law.restitution;
  const double delta_r = delta_max * (1.0 - e * e);
  if (delta <= delta_r) return 0.0;
  return law.stiffness * std::pow(delta_max, law.exponent) *
         std::pow((delta - delta_r) / (delta_max - delta_r), law.exponent);
}

void CompliantIntegrator::gaps(const double* q, const double* v, std::vector<double>& gap,
                               std::vector<double>& rate) const {
  State& s = *state_;
  const Eigen::Map<const VectorXd> qs(q, s.n), vs(v, s.n);
  if (s.linear) {
    for (Index j = 0; j < s.m; ++j) {
      double g = s.offset(j), u = 0.0;
      for (Eigen::SparseMatrix<double>::InnerIterator it(s.W, j); it; ++it) {
        g += it.value() * qs(it.row());
        u += it.value() * vs(it.row());
      }
      gap[std::size_t(j)] = g;
      rate[std::size_t(j)] = u;
    }
    return;
  }
  s.q = qs;
  s.v = vs;
  for (Index j = 0; j < s.m; ++j) {
    gap[std::size_t(j)] = system_->gap(j, s.q);
    rate[std::size_t(j)] = system_->velocity(j, s.q, s.v);
  }
}

void CompliantIntegrator::evaluate(double t, const double* y, double* dydt) {
  State& s = *state_;
  s.q = Eigen::Map<const VectorXd>(y, s.n);
  s.v = Eigen::Map<const VectorXd>(y + s.n, s.n);
  s.dynamics.evaluate(t, s.q, s.v, {});
  if (!s.linear) s.W = system_->jacobian_matrix(s.all, s.q);  // W turns with q
  s.contact.resize(s.m);
  for (Index j = 0; j < s.m; ++j) {
    double g;
    if (s.linear) {
      g = s.offset(j);
      for (Eigen::SparseMatrix<double>::InnerIterator it(s.W, j); it; ++it)
        g += it.value() * s.q(it.row());
    } else {
      g = system_->gap(j, s.q);
    }
    s.contact(j) = contact_force(std::size_t(j), -g);
  }
  s.generalized.noalias() = s.W * s.contact;
  s.dynamics.apply_inverse_mass(s.generalized);
  Eigen::Map<VectorXd>(dydt, s.n) = s.v;
  Eigen::Map<VectorXd>(dydt + s.n, s.n) = s.dynamics.free_acceleration() + s.generalized;
  Eigen::Map<VectorXd>(dydt + 2 * s.n, s.m) = s.contact;
}

void CompliantIntegrator::restart() {
  State& s = *state_;
  // after an event, the step the integration last took
  s.dense.restart(s.y, time_, s.dense.last_step() > 0.0 ? s.dense.last_step() : 1e-7);
}

kernel::StepReport CompliantIntegrator::advance(double target) {
  State& s = *state_;
  kernel::StepReport report;
  report.time = time_;
  if (target <= time_) return report;
  if (!s.dense.started()) restart();
  while (true) {
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
    if (time_ >= target) break;
  }
  finish_advance();
  report.time = time_;
  return report;
}

void CompliantIntegrator::take_step() {
  State& s = *state_;
  s.dense.step([this](const numerics::internal::DenseOutput::State& y,
                      numerics::internal::DenseOutput::State& dydt,
                      double t) { evaluate(t, y.data(), dydt.data()); });
  const double t = s.dense.time();
  if (s.dense.steps() > options_.max_steps)
    throw Error("compliant integrator: max_steps = " + std::to_string(options_.max_steps) +
                " time steps taken by t = " + to_text(t) +
                " s; the contacts' time scale is below what the tolerance and double precision "
                "resolve (check the speeds and stiffnesses, or loosen the tolerance)");
  const numerics::internal::DenseOutput::State& now = s.dense.state();
  if (!std::all_of(now.begin(), now.end(), [](double x) { return std::isfinite(x); }))
    throw Error("compliant integrator: the state is not finite at t = " + to_text(t) +
                " s; speeds, forces or stiffnesses are out of the range double precision carries");
}

bool CompliantIntegrator::next_event(double a, double b, Event& event) {
  State& s = *state_;
  estimate_gap_noise();
  auto watch = [&](double t, GapSamples& samples) {
    s.dense.state_at(t, s.probe);
    gaps(s.probe.data(), s.probe.data() + s.n, samples.gap, samples.rate);
  };
  // the quantity whose sign change the event is: the gap closing (> 0 to <= 0), opening
  // (the reverse), or a closed contact turning (u from < 0 to >= 0)
  auto signed_value = [&](EventKind kind, std::size_t i, double t) {
    s.dense.state_at(t, s.probe);
    gaps(s.probe.data(), s.probe.data() + s.n, s.gap_probe, s.rate_probe);
    return kind == EventKind::closing   ? s.gap_probe[i]
           : kind == EventKind::opening ? -s.gap_probe[i]
                                        : -s.rate_probe[i];
  };
  auto locate = [&](double t0, double t1, const GapSamples& before, const GapSamples& after,
                    std::vector<Crossing>& found) {
    for (Index j = 0; j < s.m; ++j) {
      const std::size_t i = std::size_t(j);
      const double g0 = before.gap[i], g1 = after.gap[i];
      // touching bodies at rest (behind a wave) see their gap flicker around 0 in round-off:
      // such a crossing moves no force worth a restart
      const bool gap_moved = std::max(std::abs(g0), std::abs(g1)) > s.gap_noise[i];
      EventKind kind = EventKind::none;
      if (gap_moved && g0 > 0.0 && g1 <= 0.0) {
        kind = EventKind::closing;
      } else if (gap_moved && g0 <= 0.0 && g1 > 0.0) {
        kind = EventKind::opening;
      } else if (g0 < -s.gap_noise[i] && before.rate[i] < 0.0 && after.rate[i] >= 0.0) {
        kind = EventKind::turning;
      }
      if (kind == EventKind::none) continue;
      const double f0 = kind == EventKind::closing   ? g0
                        : kind == EventKind::opening ? -g0
                                                     : -before.rate[i];
      const double f1 = kind == EventKind::closing   ? g1
                        : kind == EventKind::opening ? -g1
                                                     : -after.rate[i];
      const numerics::Bracket bracket =
          numerics::narrow_crossing([&](double t) { return signed_value(kind, i, t); }, t0, t1, f0,
                                    f1, options_.ode.event_tolerance);
      // an event at the start of the segment is the one just handled, seen again through
      // round-off of the restarted state
      if (bracket.upper <= a + options_.ode.event_tolerance) continue;
      found.push_back({j, int(kind), bracket.upper});
    }
  };
  const std::vector<Crossing> found = numerics::internal::scan_events(
      a, b, options_.ode.samples_per_step, options_.ode.event_tolerance, s.before, s.after, watch,
      locate);
  if (found.empty()) return false;
  const Crossing& earliest =
      *std::min_element(found.begin(), found.end(),
                        [](const Crossing& x, const Crossing& y) { return x.time < y.time; });
  event = {earliest.index, EventKind(earliest.kind), earliest.time};
  return true;
}

void CompliantIntegrator::end_segment(double end) {
  State& s = *state_;
  s.dense.state_at(end, s.y);
  time_ = end;
  gaps(s.y.data(), s.y.data() + s.n, s.end.gap, s.end.rate);
  for (std::size_t j = 0; j < s.end.gap.size(); ++j) {
    // a contact's force peaks where it turns, and a located turn ends a segment
    const double f = contact_force(j, -s.end.gap[j]);
    history_.force(Index(j)) = f;
    if (f > history_.max_force(Index(j))) {
      history_.max_force(Index(j)) = f;
      history_.time_of_max_force(Index(j)) = time_;
    }
    // an opening inside the round-off band is not located; the contact forgets all the same
    if (s.end.gap[j] > 0.0) max_compression_[j] = 0.0;
  }
}

bool CompliantIntegrator::handle_event(const Event& event, kernel::StepReport& report) {
  State& s = *state_;
  const std::size_t i = std::size_t(event.contact);
  if (event.kind == EventKind::opening) max_compression_[i] = 0.0;  // the contact forgets
  if (event.kind == EventKind::turning)
    max_compression_[i] = std::max(max_compression_[i], -s.end.gap[i]);
  restart();
  report.time = time_;
  report.event = event.kind != EventKind::turning;
  (event.kind == EventKind::closing ? report.closing : report.detaching).push_back(event.contact);
  // a turn only changes the contact's curve; closing and opening are the kernel's events
  return event.kind != EventKind::turning;
}

void CompliantIntegrator::finish_advance() {
  State& s = *state_;
  VectorXd q = Eigen::Map<const VectorXd>(s.y.data(), s.n),
           v = Eigen::Map<const VectorXd>(s.y.data() + s.n, s.n);
  system_->scatter_state(q, v);
  for (Index j = 0; j < s.m; ++j) history_.impulse(j) = s.y[std::size_t(2 * s.n + j)];
  history_.all_open = contacts_open();
}

void CompliantIntegrator::estimate_gap_noise() {
  State& s = *state_;
  s.gap_noise.assign(std::size_t(s.m), 0.0);
  if (!s.linear) return;  // no estimate: every crossing is located
  // g = W^T q + offset summed in floating point: a few ulps of its largest terms
  const Eigen::Map<const VectorXd> q(s.y.data(), s.n);
  for (Index j = 0; j < s.m; ++j) {
    double scale = std::abs(s.offset(j));
    for (Eigen::SparseMatrix<double>::InnerIterator it(s.W, j); it; ++it)
      scale += std::abs(it.value() * q(it.row()));
    s.gap_noise[std::size_t(j)] = 8.0 * std::numeric_limits<double>::epsilon() * scale;
  }
}

bool CompliantIntegrator::contacts_open() const {
  State& s = *state_;
  gaps(s.y.data(), s.y.data() + s.n, s.gap_probe, s.rate_probe);
  for (std::size_t j = 0; j < s.gap_probe.size(); ++j)
    if (s.gap_probe[j] <= 0.0 || s.rate_probe[j] < 0.0) return false;
  return true;
}

}  // namespace mimpact::plugins
