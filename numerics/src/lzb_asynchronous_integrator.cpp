#include "mimpact/numerics/lzb_asynchronous_integrator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "impact_input.hpp"
#include "impulse_step_rules.hpp"
#include "mimpact/common/error.hpp"

namespace mimpact::numerics {

using Eigen::Index;
using Law = LawConstants;
using Contact = LzbAsynchronousIntegrator::Contact;
using Step = LzbAsynchronousIntegrator::Step;

namespace {

// A step lasts at most this many times its neighbours' shortest: a weak contact beside a strong
// one then sees the strong one's pushes within a few of its own steps.
constexpr double kNeighbourRatio = 4.0;

// A step carries at most this share of the contact's natural impulse sqrt(E / (a H_jj)), the
// impulse over which its own kick changes its stiffness' time scale: the kicks are then stable
// and accurate for a contact holding little energy, whose delta_p step would overshoot its
// release (Stormer-Verlet's bound h < 2 / omega, with omega^2 = H_jj dF/d(delta) = a H_jj F^2 / E;
// docs/design/asynchronous_steps.md).
constexpr double kNaturalShare = 0.5;

// Below this relative change of w over a drift, the impulse absorbed is summed from its
// series rather than as the energy gained over -f u, which would cancel.
constexpr double kSeriesBelow = 1e-3;

// The queue's order: earliest first, ties to the lowest contact so runs are reproducible and
// a packing's row steps in the order of the chain it reduces to.
bool later(const Step& a, const Step& b) {
  return a.time > b.time || (a.time == b.time && a.contact > b.contact);
}

double force_of(const Law& law, double energy) {
  return energy > 0.0 ? law.coefficient * detail::power_of(energy, law.power) : 0.0;
}

// The time of a kick `length` after `time`, strictly later so that the run moves on.
double next_time(double time, double length) {
  return std::max(time + length, std::nextafter(time, INFINITY));
}

}  // namespace

LzbAsynchronousIntegrator::LzbAsynchronousIntegrator(LzbOptions options)
    : ImpulseStepIntegrator(std::move(options)) {}

void LzbAsynchronousIntegrator::take_steps(const Input& input, ImpactObserver* observer,
                                           ImpactResult& result) {
  prepare(input.diagonal, input.u_minus, input.laws);
  detail::with_columns(input.H, options().dense_up_to, dense_,
                       [&](const auto& H) { kicks(H, observer, result); });
}

void LzbAsynchronousIntegrator::prepare(const Eigen::VectorXd& diagonal,
                                        const Eigen::VectorXd& u_minus, const LawTable& laws) {
  const std::size_t m = laws.size();
  laws_ = laws.data();
  contacts_.assign(m, Contact{});
  for (std::size_t j = 0; j < m; ++j) {
    Contact& contact = contacts_[j];
    contact.h_jj = diagonal(Index(j));
    contact.tolerance_u = options().velocity_tolerance(contact.h_jj);
    contact.tolerance_energy = options().energy_tolerance(contact.h_jj);
  }
  u_.assign(u_minus.data(), u_minus.data() + m);
  queue_.clear();
  impulse_sum_ = 0.0;
}

void LzbAsynchronousIntegrator::notify(ImpactObserver* observer, std::int64_t steps, double time) {
  sampler().observe(*observer, steps, time, impulse_sum_,
                    [this](Index j, double& u, double& energy, double& force, double& impulse) {
                      const Contact& contact = contacts_[std::size_t(j)];
                      u = u_[std::size_t(j)];
                      energy = contact.energy;
                      force = force_of(laws_[std::size_t(j)], contact.energy);
                      impulse = contact.impulse;
                    });
}

void LzbAsynchronousIntegrator::schedule(Index j, double due) {
  Contact& contact = contacts_[std::size_t(j)];
  ++contact.stamp;
  contact.due = due;
  queue_.push_back(Step{due, std::uint32_t(j), contact.stamp});
  std::push_heap(queue_.begin(), queue_.end(), later);
}

// Contact j from its clock to `time` at its present u_j, exactly: w = E^(1 - a) moves at
// dw/dt = (1 - a) c sigma, sigma = -f u_j = dE/dP, and the impulse absorbed is
// integral of F dt = (E1 - E0) / sigma. In expansion the contact is released where E reaches
// its release level (0, or (1 - e^2) W_c for mono-stiffness), and then holds no energy.
void LzbAsynchronousIntegrator::drift(Index j, double time) {
  Contact& contact = contacts_[std::size_t(j)];
  const double elapsed = time - contact.clock;
  contact.clock = time;
  const double u = u_[std::size_t(j)];
  if (!contact.in_impact || elapsed <= 0.0 || (contact.energy == 0.0 && u >= 0.0)) return;
  const Law& law = laws_[std::size_t(j)];
  const bool expanding = u > 0.0;
  double f = 1.0;
  if (expanding && !law.mono_stiffness) {
    if (law.restitution == 0.0) {  // e = 0: the energy is dropped at once
      contact.energy = contact.w = 0.0;
      return;
    }
    f = law.inverse_e2;
  }
  const double sigma = -f * u;
  const double q = 1.0 - law.power;
  const double w1 = contact.w + q * law.coefficient * sigma * elapsed;
  double absorbed = 0.0;
  if (expanding && w1 <= contact.release_w) {  // released within the drift
    const double level = detail::power_of(contact.release_w, 1.0 / q);
    absorbed = contact.release_w > 0.0 ? (level - contact.energy) / sigma : -contact.energy / sigma;
    contact.energy = contact.w = 0.0;
  } else {
    const double e1 = detail::power_of(w1, 1.0 / q);
    const double x = contact.w > 0.0 ? (w1 - contact.w) / contact.w : INFINITY;
    if (std::abs(x) < kSeriesBelow) {
      // integral of (1 + x s)^b ds over [0, 1], b = a / (1 - a), to x^2
      const double b = law.power / q;
      absorbed = force_of(law, contact.energy) * elapsed *
                 (1.0 + 0.5 * b * x + b * (b - 1.0) * x * x / 6.0);
    } else {
      absorbed = (e1 - contact.energy) / sigma;
    }
    contact.energy = e1;
    contact.w = w1;
  }
  contact.absorbed += absorbed;
  contact.work -= u * absorbed;
}

// The step contact j begins at its present state: delta_p at its force when it holds energy
// (cut where an expansion releases it), the time to absorb delta_p from where it stands when it
// is entering compression; at most kNeighbourRatio times its neighbours' paces.
double LzbAsynchronousIntegrator::step_length(Index j, double limit) const {
  const Contact& contact = contacts_[std::size_t(j)];
  const Law& law = laws_[std::size_t(j)];
  const double u = u_[std::size_t(j)];
  const double q = 1.0 - law.power;
  double length = INFINITY;
  if (contact.energy > contact.tolerance_energy) {
    const double natural = std::sqrt(contact.energy / (law.power * contact.h_jj));
    length = std::min(options().delta_p, kNaturalShare * natural) / force_of(law, contact.energy);
    if (u > 0.0 && (law.mono_stiffness || law.restitution > 0.0)) {
      const double f = law.mono_stiffness ? 1.0 : law.inverse_e2;
      length = std::min(length, (contact.w - contact.release_w) / (q * law.coefficient * f * u));
    }
  } else if (u < 0.0) {
    const double target = detail::power_of(contact.energy - u * options().delta_p, q);
    length = (target - contact.w) / (q * law.coefficient * -u);
  }
  return std::max(std::min(length, limit), 0.0);
}

// The longest a step of contact j may last: kNeighbourRatio times the shortest pace of its
// neighbours in the impact (infinite when none is).
template <class Delassus>
double LzbAsynchronousIntegrator::neighbour_limit(const Delassus& H, Index j) const {
  double shortest = INFINITY;
  H.for_each_in_column(j, [&](Index i, double) {
    const Contact& neighbour = contacts_[std::size_t(i)];
    if (i != j && neighbour.in_impact) shortest = std::min(shortest, neighbour.pace);
  });
  return kNeighbourRatio * shortest;
}

// Contact j's pace has become contact.pace at `time`: a neighbour whose kick falls later than
// kNeighbourRatio times that is brought forward.
template <class Delassus>
void LzbAsynchronousIntegrator::tighten_neighbours(const Delassus& H, Index j, double time) {
  const double latest = time + kNeighbourRatio * contacts_[std::size_t(j)].pace;
  H.for_each_in_column(j, [&](Index i, double) {
    const Contact& neighbour = contacts_[std::size_t(i)];
    if (i != j && neighbour.in_impact && neighbour.due > latest) schedule(i, latest);
  });
}

// Contact j, out of the impact, is pushed into compression at `time`.
template <class Delassus>
void LzbAsynchronousIntegrator::join(const Delassus& H, Index j, double time) {
  Contact& contact = contacts_[std::size_t(j)];
  contact.in_impact = true;
  contact.energy = contact.w = contact.release_w = 0.0;
  contact.absorbed = contact.ahead = 0.0;
  contact.clock = time;
  contact.pace = step_length(j, neighbour_limit(H, j));
  schedule(j, next_time(time, contact.pace));
  tighten_neighbours(H, j, time);
}

// Contact j's kick at `time`: what it absorbed since its last kick less what it applied
// ahead then, and half of its next step's impulse ahead. A contact whose energy is below what
// the steps resolve and which no longer approaches leaves the impact, its energy dropped (the
// synchronous steps' rule).
template <class Delassus>
void LzbAsynchronousIntegrator::kick(const Delassus& H, Index j, double time) {
  drift(j, time);
  Contact& contact = contacts_[std::size_t(j)];
  const Law& law = laws_[std::size_t(j)];
  const double due = contact.absorbed - contact.ahead;
  contact.absorbed = contact.ahead = 0.0;
  if (contact.energy > contact.tolerance_energy) {
    const double force = force_of(law, contact.energy);
    if (force > contact.max_force) {
      contact.max_force = force;
      contact.time_of_max = time;
    }
    contact.pace = step_length(j, neighbour_limit(H, j));
    contact.ahead = 0.5 * force * contact.pace;
    apply_impulse(H, j, due + contact.ahead, time);
  } else {
    apply_impulse(H, j, due, time);
    if (u_[std::size_t(j)] >= -contact.tolerance_u) {
      contact.in_impact = false;
      contact.energy = contact.w = 0.0;
      contact.pace = INFINITY;
      return;
    }
    contact.pace = step_length(j, neighbour_limit(H, j));
  }
  schedule(j, next_time(time, contact.pace));
  tighten_neighbours(H, j, time);
}

// Contact j's impulse dp at `time`: u += H e_j dp, each contact touched first drifted up to
// `time` at its old u. A contact whose compression ends records W_c; one out of the impact
// pushed into compression joins it.
template <class Delassus>
void LzbAsynchronousIntegrator::apply_impulse(const Delassus& H, Index j, double dp, double time) {
  H.for_each_in_column(j, [&](Index i, double h_ij) {
    drift(i, time);
    Contact& contact = contacts_[std::size_t(i)];
    const double before = u_[std::size_t(i)];
    const double after = before + h_ij * dp;
    u_[std::size_t(i)] = after;
    if (contact.in_impact) {
      if (before < 0.0 && after >= 0.0 && contact.energy > 0.0) set_release_level(Index(i));
    } else if (i != j && after < -contact.tolerance_u) {
      join(H, i, time);
    }
  });
  Contact& contact = contacts_[std::size_t(j)];
  // compensated (Kahan) sum: a billion kicks keep P to round-off
  const double added = dp - contact.impulse_carry;
  const double sum = contact.impulse + added;
  contact.impulse_carry = (sum - contact.impulse) - added;
  contact.impulse = sum;
  impulse_sum_ += dp;
}

// Contact i's compression ends with energy W_c = E: it is released when E falls to 0 for
// bi-stiffness, to (1 - e^2) W_c for mono-stiffness (docs/model.md, section 5).
void LzbAsynchronousIntegrator::set_release_level(Index i) {
  Contact& contact = contacts_[std::size_t(i)];
  const Law& law = laws_[std::size_t(i)];
  contact.compression_work = contact.energy;
  const double e = law.restitution;
  contact.release_w = law.mono_stiffness && e < 1.0
                          ? detail::power_of((1.0 - e * e) * contact.energy, 1.0 - law.power)
                          : 0.0;
}

template <class Delassus>
void LzbAsynchronousIntegrator::kicks(const Delassus& H, ImpactObserver* observer,
                                      ImpactResult& result) {
  const Index m = Index(contacts_.size());
  for (Index j = 0; j < m; ++j)
    if (!contacts_[std::size_t(j)].in_impact &&
        u_[std::size_t(j)] < -contacts_[std::size_t(j)].tolerance_u)
      join(H, j, 0.0);

  double time = 0.0;
  if (observer) notify(observer, 0, time);
  ObserverSchedule schedule(observer, options().sample_every);
  while (!queue_.empty()) {
    std::pop_heap(queue_.begin(), queue_.end(), later);
    const Step step = queue_.back();
    queue_.pop_back();
    if (step.stamp != contacts_[step.contact].stamp) continue;  // rescheduled or cancelled
    if (result.steps >= options().max_steps) {
      result.status = ImpactStatus::step_limit;
      result.message =
          "the impact did not end within max_steps = " + std::to_string(options().max_steps) +
          " kicks; raise max_steps or delta_p";
      break;
    }
    time = step.time;
    // a clock past double precision can only stay there: the base reports the overflow (the
    // kicks ran to max_steps, 1e9 of them, before)
    if (!std::isfinite(time)) break;
    kick(H, Index(step.contact), time);
    ++result.steps;
    if (schedule.due(result.steps)) {
      const ObserverSchedule::Due due = schedule.take(result.steps);
      if (due.sample) notify(observer, result.steps, time);
      if (due.progress)
        observer->progressed(
            {.step = result.steps, .time = time, .principal_impulse = impulse_sum_});
    }
  }
  if (observer) notify(observer, result.steps, time);

  result.contact_steps = result.steps;
  result.duration = time;
  result.impulse.resize(m);
  result.max_force.resize(m);
  result.time_of_max_force.resize(m);
  result.work.resize(m);
  result.stored_energy.resize(m);
  for (Index j = 0; j < m; ++j) {
    const Contact& contact = contacts_[std::size_t(j)];
    result.impulse(j) = contact.impulse;
    result.max_force(j) = contact.max_force;
    result.time_of_max_force(j) = contact.time_of_max;
    result.work(j) = contact.work;
    result.stored_energy(j) = contact.in_impact ? contact.energy : 0.0;
  }
}

}  // namespace mimpact::numerics
