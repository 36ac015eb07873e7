#include "mimpact/numerics/impulse_step_friction.hpp"

#include <cmath>

namespace mimpact::numerics {

using Eigen::Index;
using Sparse = Eigen::SparseMatrix<double>;

void ImpulseStepFriction::prepare(const ImpactIntegrator::Input& input) {
  on_ = input.laws.frictional();
  if (!on_) return;
  rows_ = input.tangential;
  tangent_to_normal_ = input.tangent_to_normal;
  const std::size_t m = input.laws.size();
  mu_.resize(m);
  slip_work_.assign(m, 0.0);
  inverse_block_.assign(m, Eigen::Matrix2d::Zero());
  for (std::size_t j = 0; j < m; ++j) {
    mu_[j] = input.laws.friction(j);
    const int count = rows_->rows_of(Index(j));
    if (!(mu_[j] > 0.0) || count == 0) continue;
    const Index r = rows_->first_row[j];
    Eigen::Matrix2d block = Eigen::Matrix2d::Identity();
    for (int a = 0; a < count; ++a)
      for (int b = 0; b < count; ++b) block(a, b) = rows_->tangent.coeff(r + a, r + b);
    inverse_block_[j] = block.inverse();
  }
  slip_.assign(rows_->slip_minus.data(), rows_->slip_minus.data() + rows_->rows());
  impulse_.assign(std::size_t(rows_->rows()), 0.0);
}

double ImpulseStepFriction::slip_of(Index c, double* v) const {
  const Index r = rows_->first_row[std::size_t(c)];
  const int count = rows_->rows_of(c);
  v[0] = slip_[std::size_t(r)];
  v[1] = count == 2 ? slip_[std::size_t(r + 1)] : 0.0;
  return std::hypot(v[0], v[1]);
}

void ImpulseStepFriction::step(std::span<const Index> stepping, const double* step_impulse,
                               double* u) {
  stepped_.clear();
  pushed_.clear();
  for (Index c : stepping)
    if (mu_[std::size_t(c)] > 0.0 && rows_->rows_of(c) > 0) {
      Stepped entry{c, {}, {0.0, 0.0}};
      slip_of(c, entry.before);
      stepped_.push_back(entry);
    }
  if (stepped_.empty()) return;
  for (Index j : stepping)  // s += H_tn dP_n
    for (Sparse::InnerIterator it(rows_->normal_to_tangent, j); it; ++it)
      slip_[std::size_t(it.row())] += it.value() * step_impulse[j];
  for (Stepped& entry : stepped_) {
    const Index c = entry.contact;
    const int count = rows_->rows_of(c);
    double s[2];
    const double speed = slip_of(c, s);
    const double limit = mu_[std::size_t(c)] * step_impulse[c];
    Eigen::Vector2d x = -(inverse_block_[std::size_t(c)] * Eigen::Vector2d(s[0], s[1]));
    if (x.norm() > limit)
      x = speed > 0.0 ? Eigen::Vector2d(-limit * s[0] / speed, -limit * s[1] / speed)
                      : Eigen::Vector2d::Zero();
    const Index r = rows_->first_row[std::size_t(c)];
    for (int k = 0; k < count; ++k) {
      entry.impulse[k] = x(k);
      impulse_[std::size_t(r + k)] += x(k);
      for (Sparse::InnerIterator it(rows_->tangent, r + k); it; ++it)
        slip_[std::size_t(it.row())] += it.value() * x(k);
      for (Sparse::InnerIterator it(*tangent_to_normal_, r + k); it; ++it) {
        u[it.row()] += it.value() * x(k);
        pushed_.push_back(it.row());
      }
    }
  }
  // each contact's slip work by the trapezoidal rule on s over the step: summed with the normal
  // work it is the kinetic energy lost, u and s being linear in the impulses
  for (const Stepped& entry : stepped_) {
    double after[2];
    slip_of(entry.contact, after);
    for (int k = 0; k < 2; ++k)
      slip_work_[std::size_t(entry.contact)] -=
          0.5 * (entry.before[k] + after[k]) * entry.impulse[k];
  }
}

void ImpulseStepFriction::finish(ImpactResult& result) const {
  if (!on_) return;
  result.tangential_impulse =
      Eigen::Map<const Eigen::VectorXd>(impulse_.data(), Index(impulse_.size()));
  result.slip_work = Eigen::Map<const Eigen::VectorXd>(slip_work_.data(), Index(slip_work_.size()));
}

}  // namespace mimpact::numerics
