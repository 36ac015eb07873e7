#include <algorithm>

#include "mimpact/numerics/mindlin_spring.hpp"
#include "moving_group.hpp"

// A group whose contacts rub (MovingGroup::RoughLayout): spins, tangential impulses and Mindlin
// springs in its state, their right-hand side.
namespace mimpact::granular {

namespace {

Eigen::Vector3d read(const double* y, int count, double scale = 1.0) {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int k = 0; k < count; ++k) x(k) = scale * y[k];
  return x;
}

}  // namespace

void MovingGroup::restart_rough() {
  const auto d = std::size_t(dimension_);
  const std::size_t n = members_.size(), springs = springs_.list.size();
  RoughLayout& layout = rough_layout_;
  layout.spin_size = dimension_ == 3 ? 3 : 1;
  layout.spins = 2 * d * n + springs;
  layout.tangential = layout.spins + std::size_t(layout.spin_size) * n;
  layout.stretches = layout.tangential + d * springs;
  layout.works = layout.stretches + d * springs;
  y_.resize(layout.works + springs, 0.0);
  state_.spin_gain.resize(n);
  const double T = world_.time_scale;
  for (std::size_t m = 0; m < n; ++m) {
    const MovingBody& b = world_.bodies[std::size_t(members_[m])];
    const double r = world_.geometry.radius(members_[m]);
    state_.spin_gain[m] = T * b.inverse_mass / (0.4 * r);
    for (int k = 0; k < layout.spin_size; ++k)
      y_[layout.spins + std::size_t(layout.spin_size) * m + std::size_t(k)] =
          T * r * state_.spin[m](layout.spin_size == 3 ? k : 2);
  }
  for (std::size_t j = 0; j < springs; ++j) {
    const Contact& c = contacts_[std::size_t(springs_.active[j])];
    for (std::size_t k = 0; k < d; ++k)
      y_[layout.stretches + d * j + k] = c.stretch(Eigen::Index(k));
  }
}

void MovingGroup::move_rough() {
  const auto d = std::size_t(dimension_);
  const RoughLayout& layout = rough_layout_;
  const double T = world_.time_scale;
  for (std::size_t m = 0; m < members_.size(); ++m) {
    const double to_spin = 1.0 / (T * world_.geometry.radius(members_[m]));
    const double* spin = y_.data() + layout.spins + std::size_t(layout.spin_size) * m;
    state_.spin[m] = layout.spin_size == 3 ? read(spin, 3, to_spin)
                                           : Eigen::Vector3d(0.0, 0.0, to_spin * spin[0]);
  }
  for (std::int32_t index : springs_.active) {
    Contact& c = contacts_[std::size_t(index)];
    const std::size_t j = std::size_t(c.slot);
    c.tangential_impulse +=
        read(y_.data() + layout.tangential + d * j, dimension_, world_.mass_scale / T);
    c.stretch = read(y_.data() + layout.stretches + d * j, dimension_);
    c.slip_work += y_[layout.works + j] * world_.mass_scale * world_.speed_bound / T;
  }
}

template <int D>
Eigen::Vector3d MovingGroup::rolling_of(std::size_t m, const double* y) const {
  const RoughLayout& layout = rough_layout_;
  const double* spin = y + layout.spins + std::size_t(layout.spin_size) * m;
  const double inverse_T = 1.0 / world_.time_scale;
  return D == 3 ? read(spin, 3, inverse_T) : Eigen::Vector3d(0.0, 0.0, inverse_T * spin[0]);
}

template <int D>
MovingGroup::RoughKinematics MovingGroup::rough_kinematics(std::size_t j, const double* y) const {
  const Spring& s = springs_.list[j];
  const auto a = std::size_t(s.first);
  const std::size_t velocities = std::size_t(D) * members_.size();
  const double inverse_T = 1.0 / world_.time_scale;
  const Eigen::Vector3d va = read(y + velocities + std::size_t(D) * a, D, inverse_T);
  RoughKinematics k;
  k.rolling = rolling_of<D>(a, y);
  if (s.second >= 0) {
    const auto b = std::size_t(s.second);
    Eigen::Vector3d between = Eigen::Vector3d::Zero();
    for (int i = 0; i < D; ++i)
      between(i) = s.offset[i] + (y[std::size_t(D) * b + i] - y[std::size_t(D) * a + i]);
    k.distance = between.norm();
    k.normal = between / k.distance;
    k.delta = springs_.reach[j] - k.distance;
    k.relative = read(y + velocities + std::size_t(D) * b, D, inverse_T) - va;
    k.rolling += rolling_of<D>(b, y);
  } else {
    double height = springs_.aside[std::size_t(s.aside)].height;
    for (int i = 0; i < D; ++i) height += s.offset[i] * y[std::size_t(D) * a + i];
    k.normal = -s.offset;
    k.delta = springs_.reach[j] - height;
    k.relative = -va;
  }
  return k;
}

template <int D>
void MovingGroup::rhs_rough(const double* y, double* dydt) {
  const std::size_t n = members_.size(), velocities = std::size_t(D) * n;
  const RoughLayout& layout = rough_layout_;
  const double T = world_.time_scale, inverse_T = 1.0 / T;
  const double impulse_rate = T / world_.mass_scale;
  const double work_rate = T / (world_.mass_scale * world_.speed_bound);
  for (std::size_t i = 0; i < velocities; ++i) dydt[i] = y[velocities + i] * inverse_T;
  double* acceleration = dydt + velocities;
  double* spin_rate = dydt + layout.spins;
  std::fill(acceleration, acceleration + velocities, 0.0);
  std::fill(spin_rate, spin_rate + std::size_t(layout.spin_size) * n, 0.0);
  // a torque (N m) onto member m's spin's rate
  auto add_torque = [&](std::size_t m, const Eigen::Vector3d& torque) {
    double* rate = spin_rate + std::size_t(layout.spin_size) * m;
    for (int k = 0; k < layout.spin_size; ++k)  // about z alone in the plane
      rate[k] += state_.spin_gain[m] * torque(D == 3 ? k : 2);
  };
  for (std::size_t j = 0; j < springs_.list.size(); ++j) {
    const Spring& s = springs_.list[j];
    const Contact& c = contacts_[std::size_t(springs_.active[j])];
    const auto a = std::size_t(s.first);
    const RoughKinematics contact = rough_kinematics<D>(j, y);
    const Eigen::Vector3d &normal = contact.normal, &relative = contact.relative;
    const double delta = contact.delta;
    double* tangential = dydt + layout.tangential + std::size_t(D) * j;
    double* stretch_rate = dydt + layout.stretches + std::size_t(D) * j;
    if (!(delta > 0.0)) {  // open: no force, the stretch held (forgotten at the commit)
      dydt[layout.works + j] = 0.0;
      dydt[2 * velocities + j] = 0.0;
      std::fill(tangential, tangential + D, 0.0);
      std::fill(stretch_rate, stretch_rate + D, 0.0);
      continue;
    }
    const double approach = normal.dot(relative);
    const Eigen::Vector3d sliding = relative - approach * normal;
    const Eigen::Vector3d slip = sliding + normal.cross(contact.rolling);
    const Eigen::Vector3d turn =
        s.second >= 0 ? Eigen::Vector3d(sliding / contact.distance) : Eigen::Vector3d::Zero();
    const double force = c.law.force(delta);  // e = 1 (MovingContacts)
    const Eigen::Vector3d stretch = read(y + layout.stretches + std::size_t(D) * j, D);
    double friction[3] = {0.0, 0.0, 0.0}, rate[3] = {0.0, 0.0, 0.0};
    if (c.law.friction > 0.0)  // else no tangential force, and the stretch held at 0
      numerics::mindlin::rates_by_state(
          stretch.data(), slip.data(), D,
          numerics::mindlin::terms(c.law.tangential_stiffness_ratio, c.law.exponent, c.law.friction,
                                   force, delta, -approach),
          friction, rate);
    const Eigen::Vector3d tangential_force = read(friction, D);
    // the stretch stays in the tangent plane as the normal turns
    const Eigen::Vector3d stretch_rotation = stretch.dot(turn) * normal;
    const Eigen::Vector3d push = force * normal + tangential_force;  // on the second body
    const Eigen::Vector3d lever_torque = normal.cross(tangential_force);
    const double radius_a = world_.geometry.radius(members_[a]);
    for (int k = 0; k < D; ++k) acceleration[std::size_t(D) * a + k] -= state_.gain[a] * push(k);
    // the tangential force's power on the bodies (W), its torques' levers included
    double power = tangential_force.dot(sliding);
    if (s.second >= 0) {
      const auto b = std::size_t(s.second);
      const double radius_b = world_.geometry.radius(members_[b]);
      for (int k = 0; k < D; ++k) acceleration[std::size_t(D) * b + k] += state_.gain[b] * push(k);
      const Eigen::Vector3d torque_a = -(radius_a - 0.5 * delta) * lever_torque;
      const Eigen::Vector3d torque_b = -(radius_b - 0.5 * delta) * lever_torque;
      add_torque(a, torque_a);
      add_torque(b, torque_b);
      power += torque_a.dot(rolling_of<D>(a, y)) / radius_a +
               torque_b.dot(rolling_of<D>(b, y)) / radius_b;
    } else {
      const Eigen::Vector3d torque_a = -radius_a * lever_torque;
      add_torque(a, torque_a);
      power += torque_a.dot(rolling_of<D>(a, y)) / radius_a;
    }
    dydt[2 * velocities + j] = impulse_rate * force;
    dydt[layout.works + j] = -work_rate * power;
    for (int k = 0; k < D; ++k) {
      tangential[k] = impulse_rate * tangential_force(k);
      stretch_rate[k] = rate[k] - stretch_rotation(k);
    }
  }
}

template void MovingGroup::rhs_rough<2>(const double*, double*);
template void MovingGroup::rhs_rough<3>(const double*, double*);

}  // namespace mimpact::granular
