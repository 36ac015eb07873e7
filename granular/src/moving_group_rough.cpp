#include <algorithm>

#include "mimpact/numerics/mindlin_spring.hpp"
#include "moving_group.hpp"

// A group whose contacts rub (MovingGroup::RoughLayout): spins, tangential impulses and Mindlin
// springs in its state, their right-hand side.
namespace mimpact::granular {

namespace {

// A spring within this share below its cap, pushed outward, slips in the stages
// (numerics::mindlin::Terms::cap_band); in the plane one that slips throughout a step is put on
// its cap at the step's end (MovingGroup::put_on_caps), in space it is amended.
constexpr double kCapBand = 1e-3;

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
  layout.stretch_size = dimension_ == 3 ? 3 : 1;
  layout.spins = 2 * d * n + springs;
  layout.tangential = layout.spins + std::size_t(layout.spin_size) * n;
  layout.stretches = layout.tangential + d * springs;
  layout.works = layout.stretches + layout.stretch_size * springs;
  y_.resize(layout.works + springs, 0.0);
  springs_.regimes.assign(springs, 0);
  springs_.last_regime.assign(springs, 0);
  springs_.amended.clear();
  springs_.slipping.clear();
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
    if (dimension_ == 2) {
      y_[layout.stretches + j] =
          c.stretch.dot(planar_tangent(rough_kinematics<2>(j, y_.data()).normal));
      continue;
    }
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
    c.stretch = dimension_ == 2
                    ? Eigen::Vector3d(y_[layout.stretches + j] *
                                      planar_tangent(rough_kinematics<2>(j, y_.data()).normal))
                    : read(y_.data() + layout.stretches + d * j, dimension_);
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

// In the plane the contact's tangent is t = (-n_y, n_x), n x t = z: the slip along it is
// sigma = t.(v_b - v_a) - (r_a w_a + r_b w_b), the stretch xi a scalar along it (d xi/dt = sigma
// while it sticks: its turning with the normal is t's own), the tangential force f t, whose
// torque on each body is -lever f about z.
std::pair<double, double> MovingGroup::levers(std::size_t j, double delta) const {
  const Spring& s = springs_.list[j];
  const double radius_a = world_.geometry.radius(members_[std::size_t(s.first)]);
  if (s.second < 0) return {radius_a, 0.0};
  const double radius_b = world_.geometry.radius(members_[std::size_t(s.second)]);
  return {radius_a - 0.5 * delta, radius_b - 0.5 * delta};
}

MovingGroup::RoughRates MovingGroup::start_rough_rhs(const double* y, double* dydt) const {
  const std::size_t velocities = std::size_t(dimension_) * members_.size();
  const double T = world_.time_scale;
  RoughRates rates{dydt + velocities, dydt + rough_layout_.spins, 1.0 / T, T / world_.mass_scale,
                   T / (world_.mass_scale * world_.speed_bound)};
  for (std::size_t i = 0; i < velocities; ++i) dydt[i] = y[velocities + i] * rates.inverse_T;
  std::fill(rates.acceleration, rates.acceleration + velocities, 0.0);
  std::fill(rates.spin_rate,
            rates.spin_rate + std::size_t(rough_layout_.spin_size) * members_.size(), 0.0);
  return rates;
}

void MovingGroup::rhs_planar_rough(const double* y, double* dydt) {
  const std::size_t velocities = 2 * members_.size();
  const RoughLayout& layout = rough_layout_;
  const auto [acceleration, spin_rate, inverse_T, impulse_rate, work_rate] =
      start_rough_rhs(y, dydt);
  const double* spin = y + layout.spins;  // T r w
  for (std::size_t j = 0; j < springs_.list.size(); ++j) {
    const Spring& s = springs_.list[j];
    const numerics::ContactLaw& law = contacts_[std::size_t(springs_.active[j])].law;
    const RoughKinematics contact = rough_kinematics<2>(j, y);
    const double delta = contact.delta;
    double* tangential = dydt + layout.tangential + 2 * j;
    if (!(delta > 0.0)) {  // open: no force, the stretch held (forgotten at the commit)
      note_regime(j, kOpen);
      dydt[2 * velocities + j] = dydt[layout.works + j] = dydt[layout.stretches + j] = 0.0;
      tangential[0] = tangential[1] = 0.0;
      continue;
    }
    const double nx = contact.normal.x(), ny = contact.normal.y();
    const double sliding = nx * contact.relative.y() - ny * contact.relative.x();  // t.relative
    const double slip = sliding - contact.rolling.z();
    const double force = law.force(delta);  // e = 1 (MovingContacts)
    double friction = 0.0, stretch_rate = 0.0;
    if (law.friction > 0.0) {  // else no tangential force, and the stretch held at 0
      numerics::mindlin::Terms terms =
          numerics::mindlin::terms(law.tangential_stiffness_ratio, law.exponent, law.friction,
                                   force, delta, -contact.normal.dot(contact.relative));
      terms.cap_band = kCapBand;
      const auto by_state = numerics::mindlin::rates_by_state(y[layout.stretches + j], slip, terms,
                                                              friction, stretch_rate);
      note_regime(j, std::uint8_t(kUnderCap << int(by_state)));
    } else {
      note_regime(j, kUnderCap);
    }
    const double push_x = force * nx - friction * ny, push_y = force * ny + friction * nx;
    const auto a = std::size_t(s.first);
    const auto [lever_a, lever_b] = levers(j, delta);
    acceleration[2 * a] -= state_.gain[a] * push_x;
    acceleration[2 * a + 1] -= state_.gain[a] * push_y;
    spin_rate[a] -= state_.spin_gain[a] * lever_a * friction;
    // the tangential force's power on the bodies (W), its torques' levers included
    double power =
        friction * (sliding - lever_a / world_.geometry.radius(members_[a]) * spin[a] * inverse_T);
    if (s.second >= 0) {
      const auto b = std::size_t(s.second);
      acceleration[2 * b] += state_.gain[b] * push_x;
      acceleration[2 * b + 1] += state_.gain[b] * push_y;
      spin_rate[b] -= state_.spin_gain[b] * lever_b * friction;
      power -= friction * lever_b / world_.geometry.radius(members_[b]) * spin[b] * inverse_T;
    }
    dydt[2 * velocities + j] = impulse_rate * force;
    dydt[layout.works + j] = -work_rate * power;
    tangential[0] = -impulse_rate * friction * ny;
    tangential[1] = impulse_rate * friction * nx;
    dydt[layout.stretches + j] = stretch_rate;
  }
}

void MovingGroup::rhs_spatial_rough(const double* y, double* dydt) {
  constexpr int D = 3;
  const std::size_t velocities = std::size_t(D) * members_.size();
  const RoughLayout& layout = rough_layout_;
  const auto [acceleration, spin_rate, inverse_T, impulse_rate, work_rate] =
      start_rough_rhs(y, dydt);
  auto add_torque = [&](std::size_t m, const Eigen::Vector3d& torque) {  // N m
    for (std::size_t k = 0; k < 3; ++k) spin_rate[3 * m + k] += state_.spin_gain[m] * torque(k);
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
      note_regime(j, kOpen);
      dydt[layout.works + j] = dydt[2 * velocities + j] = 0.0;
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
    if (c.law.friction > 0.0) {  // else no tangential force, and the stretch held at 0
      numerics::mindlin::Terms terms =
          numerics::mindlin::terms(c.law.tangential_stiffness_ratio, c.law.exponent, c.law.friction,
                                   force, delta, -approach);
      terms.cap_band = kCapBand;
      const auto by_state =
          numerics::mindlin::rates_by_state(stretch.data(), slip.data(), D, terms, friction, rate);
      note_regime(j, std::uint8_t(kUnderCap << int(by_state)));
    } else {
      note_regime(j, kUnderCap);
    }
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

template MovingGroup::RoughKinematics MovingGroup::rough_kinematics<2>(std::size_t,
                                                                       const double*) const;
template MovingGroup::RoughKinematics MovingGroup::rough_kinematics<3>(std::size_t,
                                                                       const double*) const;
template Eigen::Vector3d MovingGroup::rolling_of<2>(std::size_t, const double*) const;

}  // namespace mimpact::granular
