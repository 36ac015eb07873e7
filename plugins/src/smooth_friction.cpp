#include "smooth_friction.hpp"

#include <Eigen/QR>

#include "contact_dynamics.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::plugins {

using kernel::Index;
using kernel::VectorXd;
using Mode = numerics::coulomb::Phase::Mode;

void SmoothFriction::initialize(const kernel::NonSmoothDynamicalSystem& system,
                                double slip_tolerance) {
  system_ = &system;
  slip_tolerance_ = slip_tolerance;
  mu_.assign(std::size_t(system.interaction_count()), 0.0);
  for (Index j = 0; j < system.interaction_count(); ++j) {
    const kernel::Interaction& contact = system.interaction(j);
    const auto* law = dynamic_cast<const LzbLaw*>(&contact.law());
    if (law && contact.relation().tangent_rows() > 0)
      mu_[std::size_t(j)] = law->contact_law().friction;
  }
  persistent_.clear();
  rubs_.clear();
}

std::vector<Index> SmoothFriction::hold(std::span<const Index> persistent, double t,
                                        const VectorXd& q, const VectorXd& v,
                                        ContactDynamics& dynamics) {
  persistent_.assign(persistent.begin(), persistent.end());
  while (true) {
    rubs_.clear();
    Index rows = 0;
    for (std::size_t k = 0; k < persistent_.size(); ++k) {
      const Index j = persistent_[k];
      if (!(mu_[std::size_t(j)] > 0.0)) continue;
      const int count = system_->interaction(j).relation().tangent_rows();
      rubs_.push_back({.contact = j, .held = k, .rows = count, .first_row = rows});
      rows += count;
    }
    if (rubs_.empty()) return persistent_;
    settle(t, q, v, dynamics);
    // friction may pull a contact the frictionless problem held: it is let go
    Index weakest = -1;
    for (std::size_t k = 0; k < persistent_.size(); ++k)
      if (normal_(Index(k)) < 0.0 && (weakest < 0 || normal_(Index(k)) < normal_(weakest)))
        weakest = Index(k);
    if (weakest < 0) return persistent_;
    persistent_.erase(persistent_.begin() + weakest);
  }
}

void SmoothFriction::settle(double t, const VectorXd& q, const VectorXd& v,
                            ContactDynamics& dynamics) {
  std::vector<Index> contacts, first_row;
  for (const Rub& rub : rubs_) contacts.push_back(rub.contact);
  const VectorXd slip = system_->tangent_matrix(contacts, q, first_row).transpose() * v;
  for (Rub& rub : rubs_)  // new, or past a switch that chooses again
    if (rub.phase.mode == Mode::choose)
      rub.phase.start(&slip(rub.first_row), rub.rows, slip_tolerance_);
  numerics::coulomb::settle_sticks(
      [&] {
        dynamics.evaluate(t, q, v, persistent_);
        accelerate(dynamics, q, v, acceleration_, normal_);
      },
      [&](auto&& visit) {
        for (Rub& rub : rubs_) visit(rub.phase, rub.force.data(), rub.rows, rub.limit);
      });
}

void SmoothFriction::accelerate(ContactDynamics& dynamics, const VectorXd& q, const VectorXd& v,
                                VectorXd& acceleration, VectorXd& normal) {
  const Index p = Index(persistent_.size());
  const Eigen::MatrixXd W(system_->jacobian_matrix(persistent_, q));
  std::vector<Index> contacts, first_row;
  for (const Rub& rub : rubs_) contacts.push_back(rub.contact);
  const Eigen::MatrixXd T(system_->tangent_matrix(contacts, q, first_row));
  auto times_inverse_mass = [&](const Eigen::MatrixXd& rows, Eigen::MatrixXd& out) {
    out = rows;
    for (Index c = 0; c < out.cols(); ++c) {
      VectorXd column = out.col(c);
      dynamics.apply_inverse_mass(column);
      out.col(c) = column;
    }
  };
  times_inverse_mass(W, mobility_);
  times_inverse_mass(T, tangent_mobility_);
  const VectorXd slip = T.transpose() * v;
  // the normal forces' accelerations, the slipping rows' forces -mu d lambda folded in
  Eigen::MatrixXd G = mobility_;
  std::vector<Index> sticking;
  std::vector<double> drift;  // c of the sticking rows
  for (Rub& rub : rubs_) {
    for (int k = 0; k < rub.rows; ++k) rub.slip[std::size_t(k)] = slip(rub.first_row + k);
    if (rub.phase.mode == Mode::slip) {
      double along[2];
      rub.phase.slip_force(mu_[std::size_t(rub.contact)], rub.slip.data(), rub.rows, along);
      for (int k = 0; k < rub.rows; ++k)
        G.col(Index(rub.held)) += along[k] * tangent_mobility_.col(rub.first_row + k);
      continue;
    }
    system_->tangent_rates(rub.contact, q, v, rates_);
    for (int k = 0; k < rub.rows; ++k) {
      sticking.push_back(rub.first_row + k);
      drift.push_back(rates_(k));
    }
  }
  const Index s = Index(sticking.size());
  Eigen::MatrixXd rows(W.rows(), p + s), pushes(W.rows(), p + s);
  rows.leftCols(p) = W;
  pushes.leftCols(p) = G;
  for (Index i = 0; i < s; ++i) {
    rows.col(p + i) = T.col(sticking[std::size_t(i)]);
    pushes.col(p + i) = tangent_mobility_.col(sticking[std::size_t(i)]);
  }
  const VectorXd& free = dynamics.free_acceleration();
  VectorXd rhs(p + s);
  rhs.head(p) = -dynamics.b();
  for (Index i = 0; i < s; ++i) rhs(p + i) = -(rows.col(p + i).dot(free) + drift[std::size_t(i)]);
  // redundant contacts (a block standing on two corners sticks by both) leave the forces
  // indeterminate: the least-norm ones
  const Eigen::MatrixXd A = rows.transpose() * pushes;
  const VectorXd forces = A.completeOrthogonalDecomposition().solve(rhs);
  acceleration = free + pushes * forces;
  normal = forces.head(p);
  Index stick = 0;
  for (Rub& rub : rubs_) {
    const double lambda = normal(Index(rub.held));
    rub.limit = mu_[std::size_t(rub.contact)] * lambda;
    if (rub.phase.mode == Mode::slip) {
      rub.phase.slip_force(rub.limit, rub.slip.data(), rub.rows, rub.force.data());
      continue;
    }
    for (int k = 0; k < rub.rows; ++k) rub.force[std::size_t(k)] = forces(p + stick++);
  }
}

void SmoothFriction::watched(VectorXd& values) const {
  values.resize(2 * Index(rubs_.size()));
  for (std::size_t r = 0; r < rubs_.size(); ++r) {
    const Rub& rub = rubs_[r];
    const std::array<double, 2> q =
        rub.phase.watched(rub.limit, rub.slip.data(), rub.force.data(), rub.rows, slip_tolerance_);
    values(2 * Index(r)) = q[0];
    values(2 * Index(r) + 1) = q[1];
  }
}

void SmoothFriction::pass(std::size_t rub, int which) {
  numerics::coulomb::Phase& phase = rubs_[rub].phase;
  phase.pass(which == 0 && phase.mode == Mode::stick);
}

}  // namespace mimpact::plugins
