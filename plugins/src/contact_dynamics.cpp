#include "contact_dynamics.hpp"

#include <algorithm>

#include "mimpact/common/error.hpp"

namespace mimpact::plugins {

void ContactDynamics::initialize(const kernel::NonSmoothDynamicalSystem& system) {
  system_ = &system;
  blocks_.clear();
  blocks_.resize(std::size_t(system.system_count()));
  for (Index k = 0; k < system.system_count(); ++k) blocks_[std::size_t(k)].describe(system, k);
  geometry_constant_ = true;
  for (Index j = 0; j < system.interaction_count(); ++j)
    geometry_constant_ = geometry_constant_ && system.interaction(j).relation().is_linear();
  dense_ = system.dof() <= kDenseUpTo;
  free_acceleration_.setZero(system.dof());
  set_.clear();
  set_valid_ = factor_valid_ = inverse_mass_valid_ = sparse_.pattern_analyzed = false;
}

void ContactDynamics::factorize_masses(const VectorXd& q) {
  for (Index k = 0; k < Index(blocks_.size()); ++k) {
    internal::MassBlock& block = blocks_[std::size_t(k)];
    if (block.constant && block.factorized) continue;
    block.q = q.segment(block.offset, block.size);
    block.refresh(system_->system(k), block.q);
    // M^-1 W_S depends on this mass
    set_valid_ = set_valid_ && block.constant;
    inverse_mass_valid_ = inverse_mass_valid_ && block.constant;
  }
}

void ContactDynamics::assemble_inverse_mass() {
  std::vector<Eigen::Triplet<double>> entries;
  for (const internal::MassBlock& block : blocks_) {
    if (block.diagonal) {
      for (Index i = 0; i < block.size; ++i)
        entries.emplace_back(block.offset + i, block.offset + i, block.inverse_diagonal(i));
    } else {
      const MatrixXd inverse = block.cholesky.solve(MatrixXd::Identity(block.size, block.size));
      for (Index c = 0; c < block.size; ++c)
        for (Index r = 0; r < block.size; ++r)
          entries.emplace_back(block.offset + r, block.offset + c, inverse(r, c));
    }
  }
  sparse_.inverse_mass.resize(system_->dof(), system_->dof());
  sparse_.inverse_mass.setFromTriplets(entries.begin(), entries.end());
  if (dense_) small_.inverse_mass = MatrixXd(sparse_.inverse_mass);
  inverse_mass_valid_ = true;
}

void ContactDynamics::assemble_set(const VectorXd& q, std::span<const Index> set) {
  const bool same_set = set_valid_ && std::equal(set.begin(), set.end(), set_.begin(), set_.end());
  if (same_set && geometry_constant_ && inverse_mass_valid_) return;
  if (!inverse_mass_valid_) assemble_inverse_mass();
  set_.assign(set.begin(), set.end());
  if (dense_)
    assemble_dense_set(q, set);
  else
    assemble_sparse_set(q, set);
  b_.resize(Index(set.size()));
  lambda_.resize(Index(set.size()));
  set_valid_ = true;
  factor_valid_ = false;
}

void ContactDynamics::assemble_dense_set(const VectorXd& q, std::span<const Index> set) {
  small_.W.setZero(system_->dof(), Index(set.size()));
  for (std::size_t k = 0; k < set.size(); ++k)
    system_->for_each_jacobian_entry(
        set[k], q, [&](Index row, double value) { small_.W(row, Index(k)) += value; });
  small_.mobility.noalias() = small_.inverse_mass * small_.W;
  small_.H.noalias() = small_.W.transpose() * small_.mobility;
}

void ContactDynamics::assemble_sparse_set(const VectorXd& q, std::span<const Index> set) {
  sparse_.W = system_->jacobian_matrix(set, q);
  sparse_.mobility = sparse_.inverse_mass * sparse_.W;
  sparse_.H = sparse_.W.transpose() * sparse_.mobility;
  // A new set, or one whose geometry moved: H keeps its sparsity pattern in the second case,
  // and then only its numerical factorization is redone.
  const bool same_pattern =
      sparse_.pattern_analyzed &&
      std::equal(sparse_.H.outerIndexPtr(), sparse_.H.outerIndexPtr() + sparse_.H.outerSize() + 1,
                 sparse_.analyzed_outer.begin(), sparse_.analyzed_outer.end()) &&
      std::equal(sparse_.H.innerIndexPtr(), sparse_.H.innerIndexPtr() + sparse_.H.nonZeros(),
                 sparse_.analyzed_inner.begin(), sparse_.analyzed_inner.end());
  if (!same_pattern) {
    sparse_.analyzed_outer.assign(sparse_.H.outerIndexPtr(),
                                  sparse_.H.outerIndexPtr() + sparse_.H.outerSize() + 1);
    sparse_.analyzed_inner.assign(sparse_.H.innerIndexPtr(),
                                  sparse_.H.innerIndexPtr() + sparse_.H.nonZeros());
    sparse_.pattern_analyzed = false;
  }
}

void ContactDynamics::evaluate(double t, const VectorXd& q, const VectorXd& v,
                               std::span<const Index> set) {
  factorize_masses(q);
  for (Index k = 0; k < Index(blocks_.size()); ++k) {
    internal::MassBlock& block = blocks_[std::size_t(k)];
    auto a = free_acceleration_.segment(block.offset, block.size);
    if (!system_->system(k).has_force()) {
      a.setZero();
      continue;
    }
    block.q = q.segment(block.offset, block.size);
    block.v = v.segment(block.offset, block.size);
    system_->system(k).force(t, block.q, block.v, block.force);
    a = block.force;
    block.apply_inverse(a);
  }
  if (set.empty()) return;
  assemble_set(q, set);
  if (dense_)
    b_.noalias() = small_.W.transpose() * free_acceleration_;
  else
    b_.noalias() = sparse_.W.transpose() * free_acceleration_;
  for (std::size_t k = 0; k < set.size(); ++k) b_(Index(k)) += system_->jacobian_rate(set[k], q, v);
}

const VectorXd& ContactDynamics::bilateral_force() {
  lambda_ = -b_;
  return solve(lambda_);
}

// H is singular when a pivot of its LDL^T vanishes against the largest: the contacts of the
// set are then redundant (e.g. two contacts on the same coordinates).
void ContactDynamics::factorize_H() {
  VectorXd pivots;
  if (dense_) {
    small_.ldlt.compute(small_.H);
    pivots = small_.ldlt.vectorD();
  } else {
    if (!sparse_.pattern_analyzed) sparse_.ldlt.analyzePattern(sparse_.H);
    sparse_.pattern_analyzed = true;
    sparse_.ldlt.factorize(sparse_.H);
    if (sparse_.ldlt.info() == Eigen::Success) pivots = sparse_.ldlt.vectorD();
  }
  if (pivots.size() == 0 || !(pivots.cwiseAbs().minCoeff() > 1e-14 * pivots.cwiseAbs().maxCoeff()))
    throw Error(
        "the persistent contacts are redundant (H is singular); the bilateral "
        "contact forces are not determined");
  factor_valid_ = true;
}

const VectorXd& ContactDynamics::solve(const VectorXd& rhs) {
  if (!factor_valid_) factorize_H();
  if (dense_)
    lambda_ = small_.ldlt.solve(rhs);
  else
    lambda_ = sparse_.ldlt.solve(rhs);
  return lambda_;
}

void ContactDynamics::acceleration(const VectorXd& lambda, VectorXd& out) const {
  out = free_acceleration_;
  if (lambda.size()) add_mobility_times(lambda, out);
}

void ContactDynamics::add_mobility_times(const VectorXd& x, VectorXd& out) const {
  if (dense_)
    out.noalias() += small_.mobility * x;
  else
    out += sparse_.mobility * x;
}

void ContactDynamics::apply_inverse_mass(VectorXd& x) const {
  for (const internal::MassBlock& block : blocks_)
    block.apply_inverse(x.segment(block.offset, block.size));
}

}  // namespace mimpact::plugins
