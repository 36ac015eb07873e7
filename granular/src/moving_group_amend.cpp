#include <algorithm>

#include "mimpact/numerics/mindlin_play.hpp"
#include "mimpact/numerics/mindlin_spatial_play.hpp"
#include "moving_group.hpp"

// A rough group's steps amended at its springs' switches, and in space where they slip
// (MovingGroup::amend_rough_step; docs/design/moving_geometry.md, "Friction within a step").
namespace mimpact::granular {

namespace {

constexpr std::array<double, 5> kNodeShares = {0.0, 0.25, 0.5, 0.75, 1.0};

using numerics::mindlin::PlanarPlay;
using numerics::mindlin::PlaySegment;
using numerics::mindlin::Regime;
using numerics::mindlin::SpatialPlay;
using numerics::mindlin::StepPolynomial;

constexpr std::size_t kMoved = 6;  // per member in `moved`: the displacement and r times the turn

// the tangent of a planar contact whose normal is interpolated (not quite of length 1)
Eigen::Vector3d tangent_of(double normal_x, double normal_y) {
  return planar_tangent({normal_x, normal_y, 0.0}).normalized();
}

// A spring's contact along the step, as polynomials in its share (in the plane the slip along
// the tangent only, slip[0])
using ContactAlongStep = SpatialPlay::Contact;

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
        (weight * h * force) * tangent_of(along.normal[0](at), along.normal[1](at));
    sums.impulse += impulse;
    sums.moment += (share - at) * impulse;
  });
  return sums;
}

// in space: f_t = -k_t xi in stick and in slip alike (there k_t r_c = mu F_n)
PlayIntegrals integrate_play(const SpatialPlay& play, const ContactAlongStep& along,
                             const numerics::ContactLaw& law, double share, double h) {
  PlayIntegrals sums;
  play.quadrature([&](double at, double weight, const Eigen::Vector3d& xi) {
    const double delta = along.overlap(at);
    if (!(delta > 0.0)) return;
    const double stiffness =
        law.tangential_stiffness_ratio * law.exponent * law.force(delta) / delta;  // e = 1
    const Eigen::Vector3d impulse = (-weight * h * stiffness) * xi;
    sums.impulse += impulse;
    sums.moment += (share - at) * impulse;
  });
  return sums;
}

}  // namespace

void MovingGroup::adjust_rough_error(std::vector<double>& error) const {
  if (dimension_ == 2)
    adjust_rough_error_in<2>(error);
  else
    adjust_rough_error_in<3>(error);
}

template <int D>
void MovingGroup::adjust_rough_error_in(std::vector<double>& error) const {
  const RoughLayout& layout = rough_layout_;
  const std::vector<double>& start = rough_->state();  // the step's start, during its attempts
  const std::size_t velocities = std::size_t(D) * members_.size(), d = std::size_t(D);
  const std::size_t spin_size = std::size_t(layout.spin_size);
  const double impulse_rate = world_.time_scale / world_.mass_scale;
  for (std::size_t j = 0; j < springs_.regimes.size(); ++j) {
    // a planar stretch that slips throughout is put back on its cap at the step's end
    // (amend_rough)
    if (D == 2 && springs_.regimes[j] == kSlipping) error[layout.stretches + j] = 0.0;
    if (!amended(springs_.regimes[j])) continue;
    const Spring& s = springs_.list[j];
    const std::size_t tangential = layout.tangential + d * j;
    Eigen::Vector3d estimate = Eigen::Vector3d::Zero();  // N s
    for (std::size_t k = 0; k < d; ++k)
      estimate(Eigen::Index(k)) = error[tangential + k] / impulse_rate;
    const RoughKinematics q = rough_kinematics<D>(j, start.data());
    const Eigen::Vector3d turn = q.normal.cross(estimate);
    const auto [lever_a, lever_b] = levers(j, q.delta);
    auto take_out = [&](std::size_t m, double sign, double lever) {
      for (std::size_t k = 0; k < d; ++k)
        error[velocities + d * m + k] -= sign * state_.gain[m] * estimate(Eigen::Index(k));
      for (std::size_t k = 0; k < spin_size; ++k)
        error[layout.spins + spin_size * m + k] +=
            state_.spin_gain[m] * lever * turn(Eigen::Index(D == 2 ? 2 : k));
    };
    take_out(std::size_t(s.first), -1.0, lever_a);
    if (s.second >= 0) take_out(std::size_t(s.second), 1.0, lever_b);
    for (std::size_t k = 0; k < d; ++k) error[tangential + k] = 0.0;
    for (std::size_t k = 0; k < layout.stretch_size; ++k)
      error[layout.stretches + layout.stretch_size * j + k] = 0.0;
    error[layout.works + j] = 0.0;
  }
}

void MovingGroup::amend_rough_step() {
  std::vector<std::size_t>& amended_springs = springs_.amended;
  amended_springs.clear();
  springs_.slipping.clear();
  for (std::size_t j = 0; j < springs_.regimes.size(); ++j) {
    if (amended(springs_.regimes[j]))
      amended_springs.push_back(j);
    else if (springs_.regimes[j] == kSlipping)
      springs_.slipping.push_back(j);  // in the plane
    springs_.regimes[j] = springs_.last_regime[j];
  }
  if (amended_springs.empty() && springs_.slipping.empty()) return;
  if (!amended_springs.empty()) sample_rough_nodes();
  world_.stats.amended_springs += std::int64_t(amended_springs.size());
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

void MovingGroup::amend_rough(double share, std::vector<double>& y) const {
  if (dimension_ == 2)
    amend_rough_in<2>(share, y);
  else
    amend_rough_in<3>(share, y);
}

// The energy the amendment gives the bodies (kinetic) and the normal springs (their bodies
// moved) is what the stages missed of the tangential forces' work: it is booked into the slip
// work, the normal springs' share by the moments that moved them, so that the ledger balances.
template <int D>
void MovingGroup::amend_rough_in(double share, std::vector<double>& y) const {
  put_on_caps(y);
  if (springs_.amended.empty()) return;
  std::vector<double> moved(kMoved * members_.size(), 0.0), moments;
  double moment_sum = 0.0;
  for (std::size_t spring : springs_.amended) {
    moments.push_back(amend_spring<D>(spring, share, y, moved));
    moment_sum += moments.back();
  }
  const double potential = move_bodies<D>(moved, y);
  if (!(moment_sum > 0.0)) return;
  const double work_rate = world_.time_scale / (world_.mass_scale * world_.speed_bound);
  for (std::size_t i = 0; i < moments.size(); ++i)
    y[rough_layout_.works + springs_.amended[i]] -= work_rate * potential * moments[i] / moment_sum;
}

template <int D>
double MovingGroup::kinetic_energy(std::size_t m, const std::vector<double>& y) const {
  const double* velocity = y.data() + std::size_t(D) * (members_.size() + m);
  // the spins are T r w: (1/2) I w^2 = (1/5) m (r w)^2
  const auto spin_size = std::size_t(rough_layout_.spin_size);
  const double* spin = y.data() + rough_layout_.spins + spin_size * m;
  double translation = 0.0, rotation = 0.0;
  for (std::size_t k = 0; k < std::size_t(D); ++k) translation += velocity[k] * velocity[k];
  for (std::size_t k = 0; k < spin_size; ++k) rotation += 0.4 * spin[k] * spin[k];
  return 0.5 / (world_.time_scale * state_.gain[m]) * (translation + rotation);
}

template <int D>
double MovingGroup::amend_spring(std::size_t j, double share, std::vector<double>& y,
                                 std::vector<double>& moved) const {
  const numerics::ContactLaw& law = contacts_[std::size_t(springs_.active[j])].law;
  if (!(law.friction > 0.0)) return 0.0;
  const RoughLayout& layout = rough_layout_;
  const double h = rough_->last_step(), T = world_.time_scale;
  const auto d = std::size_t(D);
  // the contact at the step's nodes
  std::array<std::array<double, 5>, 3> slip{}, normal{};
  std::array<double, 5> overlap{};
  for (std::size_t k = 0; k < kNodeShares.size(); ++k) {
    const RoughKinematics q = rough_kinematics<D>(j, rough_nodes_[k].data());
    const Eigen::Vector3d sliding = q.relative - q.normal.dot(q.relative) * q.normal;
    const Eigen::Vector3d moving = sliding + q.normal.cross(q.rolling);
    if constexpr (D == 2) {
      slip[0][k] = h * moving.dot(planar_tangent(q.normal));
    } else {
      for (std::size_t i = 0; i < 3; ++i) slip[i][k] = h * moving(Eigen::Index(i));
    }
    overlap[k] = q.delta;
    for (std::size_t i = 0; i < 3; ++i) normal[i][k] = q.normal(Eigen::Index(i));
  }
  ContactAlongStep along{.overlap = StepPolynomial::through(overlap)};
  for (std::size_t i = 0; i < 3; ++i) {
    along.slip[i] = StepPolynomial::through(slip[i]);
    along.normal[i] = StepPolynomial::through(normal[i]);
  }
  const std::vector<double>& y0 = rough_->start_state();
  const std::size_t stretch = layout.stretches + layout.stretch_size * j;
  const std::size_t tangential = layout.tangential + d * j;
  const double cap_ratio = law.friction / (law.tangential_stiffness_ratio * law.exponent);
  PlayIntegrals exact;
  Eigen::Vector3d final_stretch = Eigen::Vector3d::Zero();
  if constexpr (D == 2) {
    const PlanarPlay play(along.slip[0], along.overlap, cap_ratio, y0[stretch], share);
    exact = integrate_play(play, along, law, share, h);
    final_stretch(0) = play.final_stretch();
  } else {
    // the direction of a slip to the steps' own relative tolerance
    const SpatialPlay play(along, cap_ratio,
                           Eigen::Vector3d(y0[stretch], y0[stretch + 1], y0[stretch + 2]),
                           world_.options.ode.relative_tolerance, share);
    exact = integrate_play(play, along, law, share, h);
    final_stretch = play.final_stretch();
  }
  // what the stages applied, from the state: the impulse, and its moment from the nodes
  const double impulse_rate = T / world_.mass_scale;
  Eigen::Vector3d missed = exact.impulse, missed_moment = exact.moment;
  for (std::size_t k = 0; k < d; ++k) {
    std::array<double, 5> applied{};
    for (std::size_t n = 0; n < applied.size(); ++n)
      applied[n] = (rough_nodes_[n][tangential + k] - y0[tangential + k]) / impulse_rate;
    missed(Eigen::Index(k)) -= (y[tangential + k] - y0[tangential + k]) / impulse_rate;
    missed_moment(Eigen::Index(k)) -= StepPolynomial::through(applied).antiderivative()(share);
  }
  const double gained = push_missed<D>(j, missed, missed_moment, y, moved);
  for (std::size_t k = 0; k < d; ++k) y[tangential + k] += impulse_rate * missed(Eigen::Index(k));
  y[layout.works + j] -= T / (world_.mass_scale * world_.speed_bound) * gained;
  for (std::size_t k = 0; k < layout.stretch_size; ++k)
    y[stretch + k] = final_stretch(Eigen::Index(k));
  return missed_moment.norm();
}

template <int D>
double MovingGroup::push_missed(std::size_t j, const Eigen::Vector3d& missed,
                                const Eigen::Vector3d& missed_moment, std::vector<double>& y,
                                std::vector<double>& moved) const {
  const Spring& s = springs_.list[j];
  const RoughLayout& layout = rough_layout_;
  const double h = rough_->last_step(), T = world_.time_scale;
  const auto a = std::size_t(s.first), d = std::size_t(D);
  const auto b = std::size_t(std::max(s.second, 0));
  // into the bodies: the missed impulse at the share's end, its moment (times h) as what it
  // would have moved them by; its torques with the levers and normal there
  const RoughKinematics end = rough_kinematics<D>(j, y.data());
  const std::size_t velocities = d * members_.size();
  const auto spin_size = std::size_t(layout.spin_size);
  const auto [lever_a, lever_b] = levers(j, end.delta);
  const Eigen::Vector3d turn = end.normal.cross(missed);
  const Eigen::Vector3d turn_moment = end.normal.cross(missed_moment);
  auto push = [&](std::size_t m, double sign, double lever) {
    for (std::size_t k = 0; k < d; ++k) {
      y[velocities + d * m + k] += sign * state_.gain[m] * missed(Eigen::Index(k));
      moved[kMoved * m + k] += sign * h / T * state_.gain[m] * missed_moment(Eigen::Index(k));
    }
    for (std::size_t k = 0; k < spin_size; ++k) {
      const auto axis = Eigen::Index(D == 2 ? 2 : k);
      y[layout.spins + spin_size * m + k] -= state_.spin_gain[m] * lever * turn(axis);
      moved[kMoved * m + 3 + std::size_t(axis)] -=
          h / T * state_.spin_gain[m] * lever * turn_moment(axis);
    }
  };
  const double before = kinetic_energy<D>(a, y) + (s.second >= 0 ? kinetic_energy<D>(b, y) : 0.0);
  push(a, -1.0, lever_a);
  if (s.second >= 0) push(b, 1.0, lever_b);
  return kinetic_energy<D>(a, y) + (s.second >= 0 ? kinetic_energy<D>(b, y) : 0.0) - before;
}

template <int D>
double MovingGroup::move_bodies(const std::vector<double>& moved, std::vector<double>& y) const {
  const double none[kMoved] = {};
  std::vector<std::size_t> touched;  // the springs on a moved body
  double potential = 0.0;            // J: their normal springs' energy, less before the moves
  auto moves = [&](std::int32_t slot) {
    return slot >= 0 ? moved.data() + kMoved * std::size_t(slot) : none;
  };
  for (std::size_t j = 0; j < springs_.list.size(); ++j) {
    const double *first = moves(springs_.list[j].first), *second = moves(springs_.list[j].second);
    if (std::any_of(first, first + kMoved, [](double x) { return x != 0.0; }) ||
        std::any_of(second, second + kMoved, [](double x) { return x != 0.0; })) {
      touched.push_back(j);
      potential -= normal_energy<D>(j, y);
    }
  }
  for (std::size_t m = 0; m < members_.size(); ++m)
    for (std::size_t k = 0; k < std::size_t(D); ++k)
      y[std::size_t(D) * m + k] += moved[kMoved * m + k];
  for (std::size_t j : touched) {
    potential += normal_energy<D>(j, y);
    const double *first = moves(springs_.list[j].first), *second = moves(springs_.list[j].second);
    const numerics::ContactLaw& law = contacts_[std::size_t(springs_.active[j])].law;
    const RoughKinematics q = rough_kinematics<D>(j, y.data());
    if (!(law.friction > 0.0) || !(q.delta > 0.0)) continue;
    // a sticking spring's stretch moves with the slip its bodies' moves make (rhs_rough's)
    const double cap = law.friction / (law.tangential_stiffness_ratio * law.exponent) * q.delta;
    double* stretch = y.data() + rough_layout_.stretches + rough_layout_.stretch_size * j;
    if constexpr (D == 2) {
      const Eigen::Vector3d tangent = planar_tangent(q.normal);
      if (!(std::abs(*stretch) < cap)) continue;
      const double slid = tangent.x() * (second[0] - first[0]) +
                          tangent.y() * (second[1] - first[1]) - (first[5] + second[5]);
      *stretch = std::clamp(*stretch + slid, -cap, cap);
    } else {
      Eigen::Map<Eigen::Vector3d> xi(stretch);
      if (!(xi.norm() < cap)) continue;
      const Eigen::Vector3d across(second[0] - first[0], second[1] - first[1],
                                   second[2] - first[2]);
      const Eigen::Vector3d turned(first[3] + second[3], first[4] + second[4],
                                   first[5] + second[5]);
      xi += across - across.dot(q.normal) * q.normal + q.normal.cross(turned);
      if (xi.norm() > cap) xi *= cap / xi.norm();
    }
  }
  return potential;
}

template <int D>
double MovingGroup::normal_energy(std::size_t j, const std::vector<double>& y) const {
  const numerics::ContactLaw& law = contacts_[std::size_t(springs_.active[j])].law;
  return numerics::hysteresis_energy(law, rough_kinematics<D>(j, y.data()).delta, 0.0);  // e = 1
}

}  // namespace mimpact::granular
