#include "mimpact/plugins/compliant_integrator.hpp"

#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <functional>
#include <limits>

#include "mimpact/numerics/error.hpp"
#include "mimpact/numerics/root_bracketing.hpp"
#include "mimpact/plugins/contact_dynamics.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::plugins {

namespace odeint = boost::numeric::odeint;

bool CompliantOptions::is_valid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  auto finite_positive = [](double x) { return x > 0.0 && std::isfinite(x); };
  if (!finite_positive(absolute_tolerance))
    return fail(invalid_value_message("absolute_tolerance", absolute_tolerance, "a finite value > 0"));
  if (!finite_positive(relative_tolerance))
    return fail(invalid_value_message("relative_tolerance", relative_tolerance, "a finite value > 0"));
  if (!(max_step >= 0.0 && std::isfinite(max_step)))
    return fail(invalid_value_message("max_step", max_step, "a finite value >= 0 (s, 0 for none)"));
  if (!finite_positive(event_tolerance))
    return fail(invalid_value_message("event_tolerance", event_tolerance, "a finite value > 0 (s)"));
  if (samples_per_step < 1) return fail(invalid_value_message("samples_per_step", samples_per_step, ">= 1"));
  if (max_steps < 1) return fail(invalid_value_message("max_steps", double(max_steps), "an integer >= 1"));
  return true;
}

// y = (q, v, P): positions, velocities and the impulse of every contact.
struct CompliantIntegrator::State {
  using Vector = std::vector<double>;
  using Stepper = odeint::runge_kutta_dopri5<Vector>;
  using Dense = odeint::result_of::make_dense_output<Stepper>::type;

  explicit State(const CompliantOptions& o)
      : dense(o.max_step > 0.0 ? odeint::make_dense_output(o.absolute_tolerance, o.relative_tolerance, o.max_step, Stepper())
                               : odeint::make_dense_output(o.absolute_tolerance, o.relative_tolerance, Stepper())) {}

  Dense dense;
  Vector y, probe;
  Index n = 0, m = 0;
  bool linear = true;
  std::vector<Index> all;         // every interaction
  Eigen::SparseMatrix<double> W;  // dof x contacts, constant when every relation is linear
  VectorXd offset;                // g = W^T q + offset for linear relations
  ContactDynamics dynamics;
  VectorXd q, v, generalized, contact;  // right-hand side workspace
  std::vector<double> gap, rate, gap_next, rate_next;
  // the round-off of each gap (m): a crossing within it is noise, not a contact event
  std::vector<double> gap_noise;
  std::vector<double> gap_probe, rate_probe;  // scratch of the root finder and the open test
  bool started = false;
  double last_step = 1e-7;  // s: the step the integration restarts with after an event
  std::int64_t steps = 0;   // time steps taken since initialize()
};

namespace {

// What ends a segment of the integration at a contact.
enum class EventKind { none, closing, opening, turning };

}  // namespace

CompliantIntegrator::CompliantIntegrator(CompliantOptions options) : options_(options) {
  std::string why;
  if (!options_.is_valid(&why)) throw InvalidInput("compliant integrator: " + why);
}

CompliantIntegrator::~CompliantIntegrator() = default;

std::unique_ptr<kernel::OneStepIntegrator> CompliantIntegrator::create(const kernel::Parameters& parameters) {
  parameters.allow_only("integrator \"compliant\"", {"absolute_tolerance", "relative_tolerance", "max_step",
                                                      "event_tolerance", "samples_per_step", "max_steps"});
  CompliantOptions o;
  o.absolute_tolerance = parameters.get("absolute_tolerance", o.absolute_tolerance);
  o.relative_tolerance = parameters.get("relative_tolerance", o.relative_tolerance);
  o.max_step = parameters.get("max_step", o.max_step);
  o.event_tolerance = parameters.get("event_tolerance", o.event_tolerance);
  o.samples_per_step = int(parameters.get_integer("samples_per_step", o.samples_per_step, 1, 1'000'000));
  o.max_steps = parameters.get_integer("max_steps", o.max_steps, 1, std::int64_t(1) << 62);
  return std::make_unique<CompliantIntegrator>(o);
}

void CompliantIntegrator::initialize(kernel::NonSmoothDynamicalSystem& system, double start,
                                     kernel::ImpactProblem&, kernel::ContactForceProblem&) {
  system_ = &system;
  time_ = start;
  state_ = std::make_unique<State>(options_);
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
                         "(LZB.md section 3); a mono-stiffness law with e < 1 has no time-domain form here");
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
  s.gap.resize(std::size_t(s.m));
  s.rate = s.gap_next = s.rate_next = s.gap_probe = s.rate_probe = s.gap;
  // a contact that starts compressed (a static load) starts on its loading curve
  max_compression_.assign(std::size_t(s.m), 0.0);
  force_.assign(std::size_t(s.m), 0.0);
  max_force_ = time_of_max_ = impulse_ = force_;
  gaps(s.y.data(), s.y.data() + s.n, s.gap, s.rate);
  for (Index j = 0; j < s.m; ++j) {
    force_[std::size_t(j)] = contact_force(std::size_t(j), -s.gap[std::size_t(j)]);
    max_force_[std::size_t(j)] = force_[std::size_t(j)];
    max_compression_[std::size_t(j)] = std::max(0.0, -s.gap[std::size_t(j)]);
  }
  s.started = false;
}

double CompliantIntegrator::contact_force(std::size_t j, double delta) const {
  if (!(delta > 0.0)) return 0.0;
  const numerics::ContactLaw& law = laws_[j];
  const double delta_max = max_compression_[j];
  if (delta >= delta_max || law.restitution >= 1.0) return law.stiffness * std::pow(delta, law.exponent);
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
      for (Eigen::SparseMatrix<double>::InnerIterator it(s.W, j); it; ++it) g += it.value() * s.q(it.row());
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
  s.dense.initialize(s.y, time_, s.last_step);
  s.started = true;
}

kernel::StepReport CompliantIntegrator::advance(double target) {
  State& s = *state_;
  kernel::StepReport report;
  report.time = time_;
  if (target <= time_) return report;
  auto rhs = [this](const State::Vector& y, State::Vector& dydt, double t) {
    evaluate(t, y.data(), dydt.data());
  };
  if (!s.started) restart();
  while (true) {
    if (s.dense.current_time() <= time_) {
      const auto [from, to] = s.dense.do_step(rhs);
      s.last_step = to - from;
      ++report.smooth_steps;
      if (++s.steps > options_.max_steps)
        throw Error("compliant integrator: max_steps = " + std::to_string(options_.max_steps) +
                    " time steps taken by t = " + to_text(to) +
                    " s; the contacts' time scale is below what the tolerance and double precision "
                    "resolve (check the speeds and stiffnesses, or loosen the tolerance)");
      const State::Vector& now = s.dense.current_state();
      if (!std::all_of(now.begin(), now.end(), [](double x) { return std::isfinite(x); }))
        throw Error("compliant integrator: the state is not finite at t = " + to_text(to) +
                    " s; speeds, forces or stiffnesses are out of the range double precision carries");
      continue;
    }
    const double a = time_, b = std::min(s.dense.current_time(), target);
    // events: a gap crossing 0 either way, or a closed contact turning (u from < 0 to >= 0)
    auto at = [&](double t, std::vector<double>& gap, std::vector<double>& rate) {
      s.dense.calc_state(t, s.probe);
      gaps(s.probe.data(), s.probe.data() + s.n, gap, rate);
    };
    at(a, s.gap, s.rate);
    estimate_gap_noise();
    double t_previous = a, event_time = INFINITY;
    Index event_contact = -1;
    EventKind event_kind = EventKind::none;
    for (int k = 1; k <= options_.samples_per_step && event_contact < 0; ++k) {
      const double t = k == options_.samples_per_step ? b : a + (b - a) * k / options_.samples_per_step;
      at(t, s.gap_next, s.rate_next);
      for (Index j = 0; j < s.m; ++j) {
        const std::size_t i = std::size_t(j);
        auto gap_of = [&](double x) {
          s.dense.calc_state(x, s.probe);
          gaps(s.probe.data(), s.probe.data() + s.n, s.gap_probe, s.rate_probe);
          return std::pair{s.gap_probe[i], s.rate_probe[i]};
        };
        EventKind kind = EventKind::none;
        double lower = t_previous, upper = t, f_lower = 0.0, f_upper = 0.0;
        std::function<double(double)> f;
        // touching bodies at rest (behind a wave) see their gap flicker around 0 in round-off:
        // such a crossing moves no force worth a restart
        const bool gap_moved = std::max(std::abs(s.gap[i]), std::abs(s.gap_next[i])) > s.gap_noise[i];
        if (gap_moved && s.gap[i] > 0.0 && s.gap_next[i] <= 0.0) {
          kind = EventKind::closing;
          f = [&](double x) { return gap_of(x).first; };
          f_lower = s.gap[i];
          f_upper = s.gap_next[i];
        } else if (gap_moved && s.gap[i] <= 0.0 && s.gap_next[i] > 0.0) {
          kind = EventKind::opening;
          f = [&](double x) { return -gap_of(x).first; };
          f_lower = -s.gap[i];
          f_upper = -s.gap_next[i];
        } else if (s.gap[i] < -s.gap_noise[i] && s.rate[i] < 0.0 && s.rate_next[i] >= 0.0) {
          kind = EventKind::turning;
          f = [&](double x) { return -gap_of(x).second; };
          f_lower = -s.rate[i];
          f_upper = -s.rate_next[i];
        }
        if (kind == EventKind::none) continue;
        const numerics::Bracket bracket =
            numerics::narrow_crossing(f, lower, upper, f_lower, f_upper, options_.event_tolerance);
        // an event at the start of the segment is the one just handled, seen again through
        // round-off of the restarted state
        if (bracket.upper <= a + options_.event_tolerance) continue;
        if (bracket.upper < event_time) {
          event_time = bracket.upper;
          event_contact = j;
          event_kind = kind;
        }
      }
      std::swap(s.gap, s.gap_next);
      std::swap(s.rate, s.rate_next);
      t_previous = t;
    }
    const double end = event_contact >= 0 ? event_time : b;
    s.dense.calc_state(end, s.y);
    time_ = end;
    account_segment_end();
    if (event_contact >= 0) {
      const std::size_t i = std::size_t(event_contact);
      std::vector<double> g(std::size_t(s.m)), u(std::size_t(s.m));
      gaps(s.y.data(), s.y.data() + s.n, g, u);
      if (event_kind == EventKind::opening) max_compression_[i] = 0.0;  // the contact forgets
      if (event_kind == EventKind::turning) max_compression_[i] = std::max(max_compression_[i], -g[i]);
      restart();
      report.time = time_;
      report.event = event_kind != EventKind::turning;
      (event_kind == EventKind::closing ? report.closing : report.detaching).push_back(event_contact);
      if (event_kind != EventKind::turning) break;
      continue;
    }
    if (end >= target) break;
  }
  VectorXd q = Eigen::Map<const VectorXd>(s.y.data(), s.n), v = Eigen::Map<const VectorXd>(s.y.data() + s.n, s.n);
  system_->scatter_state(q, v);
  for (Index j = 0; j < s.m; ++j) impulse_[std::size_t(j)] = s.y[std::size_t(2 * s.n + j)];
  report.time = time_;
  return report;
}

void CompliantIntegrator::estimate_gap_noise() {
  State& s = *state_;
  s.gap_noise.assign(std::size_t(s.m), 0.0);
  if (!s.linear) return;  // no estimate: every crossing is located
  // g = W^T q + offset summed in floating point: a few ulps of its largest terms
  const Eigen::Map<const VectorXd> q(s.y.data(), s.n);
  for (Index j = 0; j < s.m; ++j) {
    double scale = std::abs(s.offset(j));
    for (Eigen::SparseMatrix<double>::InnerIterator it(s.W, j); it; ++it) scale += std::abs(it.value() * q(it.row()));
    s.gap_noise[std::size_t(j)] = 8.0 * std::numeric_limits<double>::epsilon() * scale;
  }
}

void CompliantIntegrator::account_segment_end() {
  State& s = *state_;
  gaps(s.y.data(), s.y.data() + s.n, s.gap_next, s.rate_next);
  for (std::size_t j = 0; j < s.gap_next.size(); ++j) {
    // a contact's force peaks where it turns, and a located turn ends a segment
    const double f = contact_force(j, -s.gap_next[j]);
    force_[j] = f;
    if (f > max_force_[j]) {
      max_force_[j] = f;
      time_of_max_[j] = time_;
    }
    // an opening inside the round-off band is not located; the contact forgets all the same
    if (s.gap_next[j] > 0.0) max_compression_[j] = 0.0;
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
