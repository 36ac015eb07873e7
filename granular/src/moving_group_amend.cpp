#include <algorithm>

#include "mimpact/numerics/mindlin_play.hpp"
#include "moving_group.hpp"

// A planar rough group's steps amended at its springs' switches (MovingGroup::amend_rough_step;
// docs/design/moving_geometry.md, "Friction within a step").
namespace mimpact::granular {

namespace {

constexpr std::array<double, 5> kNodeShares = {0.0, 0.25, 0.5, 0.75, 1.0};

using numerics::mindlin::PlanarPlay;
using numerics::mindlin::PlaySegment;
using numerics::mindlin::Regime;
using numerics::mindlin::StepPolynomial;

// the tangent of a planar contact whose normal is interpolated (not quite of length 1)
Eigen::Vector3d tangent_of(double normal_x, double normal_y) {
  return planar_tangent({normal_x, normal_y, 0.0}).normalized();
}

// A spring's contact along the step, as polynomials in its share: the slip along the tangent
// times the step (m), the overlap (m) and the normal.
struct ContactAlongStep {
  StepPolynomial slip, overlap, normal_x, normal_y;
};

// The spring's tangential force integrated along its play (N s): the impulse on the second
// body, and its moment about the share `share` (the integral of the impulse so far over the
// step's share).
struct PlayIntegrals {
  Eigen::Vector3d impulse = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
};

PlayIntegrals integrate_play(const PlanarPlay& play, const ContactAlongStep& along,
                             const numerics::ContactLaw& law, double share, double h) {
  PlayIntegrals sums;
  play.quadrature([&](double at, double weight, double xi, const PlaySegment& segment) {
    const double delta = along.overlap(at);
    if (!(delta > 0.0)) return;
    const double normal_force = law.force(delta);  // e = 1 (MovingContacts)
    const double force =
        segment.regime == Regime::slip
            ? -segment.sign * law.friction * normal_force
            : -law.tangential_stiffness_ratio * law.exponent * normal_force / delta * xi;
    const Eigen::Vector3d impulse =
        (weight * h * force) * tangent_of(along.normal_x(at), along.normal_y(at));
    sums.impulse += impulse;
    sums.moment += (share - at) * impulse;
  });
  return sums;
}

}  // namespace

void MovingGroup::adjust_rough_error(std::vector<double>& error) const {
  if (dimension_ != 2) return;
  const RoughLayout& layout = rough_layout_;
  const std::vector<double>& start = rough_->state();  // the step's start, during its attempts
  const std::size_t velocities = 2 * members_.size();
  const double impulse_rate = world_.time_scale / world_.mass_scale;
  for (std::size_t j = 0; j < springs_.regimes.size(); ++j) {
    // a stretch that slips throughout is put back on its cap at the step's end (amend_rough)
    if (springs_.regimes[j] == kSlipping) error[layout.stretches + j] = 0.0;
    if (!switching(springs_.regimes[j])) continue;
    const Spring& s = springs_.list[j];
    const std::size_t tangential = layout.tangential + 2 * j;
    const Eigen::Vector3d estimate(error[tangential] / impulse_rate,
                                   error[tangential + 1] / impulse_rate, 0.0);  // N s
    const RoughKinematics q = rough_kinematics<2>(j, start.data());
    const double turn = q.normal.x() * estimate.y() - q.normal.y() * estimate.x();
    const auto [lever_a, lever_b] = levers(j, q.delta);
    const auto a = std::size_t(s.first);
    for (std::size_t k = 0; k < 2; ++k) {
      error[velocities + 2 * a + k] += state_.gain[a] * estimate(Eigen::Index(k));
      error[tangential + k] = 0.0;
    }
    error[layout.spins + a] += state_.spin_gain[a] * lever_a * turn;
    if (s.second >= 0) {
      const auto b = std::size_t(s.second);
      for (std::size_t k = 0; k < 2; ++k)
        error[velocities + 2 * b + k] -= state_.gain[b] * estimate(Eigen::Index(k));
      error[layout.spins + b] += state_.spin_gain[b] * lever_b * turn;
    }
    error[layout.works + j] = error[layout.stretches + j] = 0.0;
  }
}

void MovingGroup::amend_rough_step() {
  std::vector<std::size_t>& amended = springs_.amended;
  amended.clear();
  springs_.slipping.clear();
  for (std::size_t j = 0; j < springs_.regimes.size(); ++j) {
    if (switching(springs_.regimes[j])) amended.push_back(j);
    if (springs_.regimes[j] == kSlipping) springs_.slipping.push_back(j);
    springs_.regimes[j] = springs_.last_regime[j];
  }
  if (amended.empty() && springs_.slipping.empty()) return;
  if (!amended.empty()) sample_rough_nodes();
  world_.stats.amended_springs += std::int64_t(amended.size());
  amend_rough(1.0, rough_->amend_end());
}

void MovingGroup::sample_rough_nodes() {
  const auto prefix = std::ptrdiff_t(rough_layout_.stretches);
  const double start = rough_->time() - rough_->last_step();
  for (std::size_t k = 0; k < kNodeShares.size(); ++k) {
    std::vector<double>& node = rough_nodes_[k];
    if (k == 0 || k + 1 == kNodeShares.size()) {  // the step's own ends, before the amendment
      const std::vector<double>& end = k == 0 ? rough_->start_state() : rough_->state();
      node.assign(end.begin(), end.begin() + prefix);
      continue;
    }
    const auto weights = rough_->weights_at(start + kNodeShares[k] * rough_->last_step());
    node.resize(std::size_t(prefix));
    for (std::size_t i = 0; i < node.size(); ++i) node[i] = rough_->component_at(weights, i);
  }
}

void MovingGroup::put_on_caps(std::vector<double>& y) const {
  for (std::size_t j : springs_.slipping) {
    const numerics::ContactLaw& law = contacts_[std::size_t(springs_.active[j])].law;
    const RoughKinematics q = rough_kinematics<2>(j, y.data());
    if (!(law.friction > 0.0) || !(q.delta > 0.0)) continue;
    double& stretch = y[rough_layout_.stretches + j];
    stretch = std::copysign(
        law.friction / (law.tangential_stiffness_ratio * law.exponent) * q.delta, stretch);
  }
}

// The energy the amendment gives the bodies (kinetic) and the normal springs (their bodies
// moved) is what the stages missed of the tangential forces' work: it is booked into the slip
// work, the normal springs' share by the moments that moved them, so that the ledger balances.
void MovingGroup::amend_rough(double share, std::vector<double>& y) const {
  put_on_caps(y);
  if (springs_.amended.empty()) return;
  std::vector<double> moved(3 * members_.size(), 0.0), moments;
  double moment_sum = 0.0;
  for (std::size_t spring : springs_.amended) {
    moments.push_back(amend_spring(spring, share, y, moved));
    moment_sum += moments.back();
  }
  const double potential = move_bodies(moved, y);
  if (!(moment_sum > 0.0)) return;
  const double work_rate = world_.time_scale / (world_.mass_scale * world_.speed_bound);
  for (std::size_t i = 0; i < moments.size(); ++i)
    y[rough_layout_.works + springs_.amended[i]] -= work_rate * potential * moments[i] / moment_sum;
}

double MovingGroup::kinetic_energy(std::size_t m, const std::vector<double>& y) const {
  const double* velocity = y.data() + 2 * (members_.size() + m);
  const double spin = y[rough_layout_.spins + m];  // T r w: (1/2) I w^2 = (1/5) m (r w)^2
  return 0.5 / (world_.time_scale * state_.gain[m]) *
         (velocity[0] * velocity[0] + velocity[1] * velocity[1] + 0.4 * spin * spin);
}

double MovingGroup::amend_spring(std::size_t j, double share, std::vector<double>& y,
                                 std::vector<double>& moved) const {
  const Spring& s = springs_.list[j];
  const numerics::ContactLaw& law = contacts_[std::size_t(springs_.active[j])].law;
  if (!(law.friction > 0.0)) return 0.0;
  const RoughLayout& layout = rough_layout_;
  const double h = rough_->last_step(), T = world_.time_scale;
  const auto a = std::size_t(s.first);
  const auto b = std::size_t(std::max(s.second, 0));
  // the contact at the step's nodes
  std::array<double, 5> slip{}, overlap{}, normal_x{}, normal_y{};
  for (std::size_t k = 0; k < kNodeShares.size(); ++k) {
    const double* node = rough_nodes_[k].data();
    const RoughKinematics q = rough_kinematics<2>(j, node);
    const Eigen::Vector3d tangent = planar_tangent(q.normal);
    const Eigen::Vector3d sliding = q.relative - q.normal.dot(q.relative) * q.normal;
    slip[k] = h * (sliding + q.normal.cross(q.rolling)).dot(tangent);
    overlap[k] = q.delta;
    normal_x[k] = q.normal.x();
    normal_y[k] = q.normal.y();
  }
  const ContactAlongStep along{StepPolynomial::through(slip), StepPolynomial::through(overlap),
                               StepPolynomial::through(normal_x),
                               StepPolynomial::through(normal_y)};
  const std::vector<double>& y0 = rough_->start_state();
  const std::size_t stretch = layout.stretches + j, tangential = layout.tangential + 2 * j;
  const PlanarPlay play(along.slip, along.overlap,
                        law.friction / (law.tangential_stiffness_ratio * law.exponent), y0[stretch],
                        share);
  const PlayIntegrals exact = integrate_play(play, along, law, share, h);
  // what the stages applied, from the state: the impulse, and its moment from the nodes
  const double impulse_rate = T / world_.mass_scale;
  Eigen::Vector3d missed = exact.impulse, missed_moment = exact.moment;
  for (std::size_t k = 0; k < 2; ++k) {
    std::array<double, 5> applied{};
    for (std::size_t n = 0; n < applied.size(); ++n)
      applied[n] = (rough_nodes_[n][tangential + k] - y0[tangential + k]) / impulse_rate;
    missed(Eigen::Index(k)) -= (y[tangential + k] - y0[tangential + k]) / impulse_rate;
    missed_moment(Eigen::Index(k)) -= StepPolynomial::through(applied).antiderivative()(share);
  }
  // into the bodies: the missed impulse at the share's end, its moment (times h) as what it
  // would have moved them by; its torques with the levers and normal there
  const RoughKinematics end = rough_kinematics<2>(j, y.data());
  const std::size_t velocities = 2 * members_.size();
  const auto [lever_a, lever_b] = levers(j, end.delta);
  auto push = [&](std::size_t m, double sign, double lever) {
    const double turn = end.normal.x() * missed.y() - end.normal.y() * missed.x();  // (n x p).z
    const double turn_moment =
        end.normal.x() * missed_moment.y() - end.normal.y() * missed_moment.x();
    for (std::size_t k = 0; k < 2; ++k) {
      y[velocities + 2 * m + k] += sign * state_.gain[m] * missed(Eigen::Index(k));
      moved[3 * m + k] += sign * h / T * state_.gain[m] * missed_moment(Eigen::Index(k));
    }
    y[layout.spins + m] -= state_.spin_gain[m] * lever * turn;
    moved[3 * m + 2] -= h / T * state_.spin_gain[m] * lever * turn_moment;
  };
  const double before = kinetic_energy(a, y) + (s.second >= 0 ? kinetic_energy(b, y) : 0.0);
  push(a, -1.0, lever_a);
  if (s.second >= 0) push(b, 1.0, lever_b);
  const double gained =
      kinetic_energy(a, y) + (s.second >= 0 ? kinetic_energy(b, y) : 0.0) - before;
  for (std::size_t k = 0; k < 2; ++k) y[tangential + k] += impulse_rate * missed(Eigen::Index(k));
  y[layout.works + j] -= T / (world_.mass_scale * world_.speed_bound) * gained;
  y[stretch] = play.final_stretch();
  return missed_moment.norm();
}

double MovingGroup::move_bodies(const std::vector<double>& moved, std::vector<double>& y) const {
  const double none[3] = {0.0, 0.0, 0.0};
  std::vector<std::size_t> touched;  // the springs on a moved body
  double potential = 0.0;            // J: their normal springs' energy, less before the moves
  for (std::size_t j = 0; j < springs_.list.size(); ++j) {
    const Spring& s = springs_.list[j];
    const double* first = moved.data() + 3 * std::size_t(s.first);
    const double* second = s.second >= 0 ? moved.data() + 3 * std::size_t(s.second) : none;
    if (std::any_of(first, first + 3, [](double x) { return x != 0.0; }) ||
        std::any_of(second, second + 3, [](double x) { return x != 0.0; })) {
      touched.push_back(j);
      potential -= normal_energy(j, y);
    }
  }
  for (std::size_t m = 0; m < members_.size(); ++m)
    for (std::size_t k = 0; k < 2; ++k) y[2 * m + k] += moved[3 * m + k];
  for (std::size_t j : touched) {
    potential += normal_energy(j, y);
    const Spring& s = springs_.list[j];
    const double* first = moved.data() + 3 * std::size_t(s.first);
    const double* second = s.second >= 0 ? moved.data() + 3 * std::size_t(s.second) : none;
    const numerics::ContactLaw& law = contacts_[std::size_t(springs_.active[j])].law;
    const RoughKinematics q = rough_kinematics<2>(j, y.data());
    if (!(law.friction > 0.0) || !(q.delta > 0.0)) continue;
    // a sticking spring's stretch moves with the slip its bodies' moves make (rhs_rough's)
    const Eigen::Vector3d tangent = planar_tangent(q.normal);
    double& stretch = y[rough_layout_.stretches + j];
    const double cap = law.friction / (law.tangential_stiffness_ratio * law.exponent) * q.delta;
    if (!(std::abs(stretch) < cap)) continue;
    const double slid = tangent.x() * (second[0] - first[0]) +
                        tangent.y() * (second[1] - first[1]) - (first[2] + second[2]);
    stretch = std::clamp(stretch + slid, -cap, cap);
  }
  return potential;
}

double MovingGroup::normal_energy(std::size_t j, const std::vector<double>& y) const {
  const numerics::ContactLaw& law = contacts_[std::size_t(springs_.active[j])].law;
  return numerics::hysteresis_energy(law, rough_kinematics<2>(j, y.data()).delta, 0.0);  // e = 1
}

}  // namespace mimpact::granular
