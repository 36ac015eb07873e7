#include "mimpact/kernel/non_smooth_dynamical_system.hpp"

#include "mimpact/common/error.hpp"

namespace mimpact::kernel {

Index NonSmoothDynamicalSystem::add(std::shared_ptr<DynamicalSystem> system) {
  if (!system) throw InvalidInput("add(): a null dynamical system");
  if (index_of_.count(system.get()))
    throw InvalidInput("system '" + system->name() + "' is added twice");
  const Index k = Index(systems_.size());
  index_of_[system.get()] = k;
  offsets_.push_back(dof_);
  dof_ += system->dimension();
  touching_.emplace_back();
  systems_.push_back(std::move(system));
  return k;
}

Index NonSmoothDynamicalSystem::add(std::shared_ptr<Interaction> interaction) {
  if (!interaction) throw InvalidInput("add(): a null interaction");
  auto index = [&](const std::shared_ptr<DynamicalSystem>& system) -> Index {
    if (!system) return -1;
    const auto found = index_of_.find(system.get());
    if (found == index_of_.end())
      throw InvalidInput("interaction '" + interaction->name() + "' joins system '" +
                         system->name() + "', which is not part of the system; add it first");
    return found->second;
  };
  const Index j = Index(interactions_.size());
  Link link{index(interaction->first()), index(interaction->second())};
  touching_[link.first].push_back(j);
  if (link.second >= 0) touching_[link.second].push_back(j);
  links_.push_back(link);
  workspaces_.push_back({VectorXd(interaction->dimension()), VectorXd(interaction->dimension()),
                         RowVectorXd(interaction->dimension())});
  interactions_.push_back(std::move(interaction));
  return j;
}

bool NonSmoothDynamicalSystem::has_force() const {
  for (const auto& system : systems_)
    if (system->has_force()) return true;
  return false;
}

bool NonSmoothDynamicalSystem::mass_is_diagonal() const {
  for (const auto& system : systems_)
    if (!system->mass_is_diagonal()) return false;
  return true;
}

bool NonSmoothDynamicalSystem::mass_is_constant() const {
  for (const auto& system : systems_)
    if (!system->mass_is_constant()) return false;
  return true;
}

void NonSmoothDynamicalSystem::gather_state(VectorXd& q, VectorXd& v) const {
  q.resize(dof_);
  v.resize(dof_);
  for (std::size_t k = 0; k < systems_.size(); ++k) {
    q.segment(offsets_[k], systems_[k]->dimension()) = systems_[k]->position();
    v.segment(offsets_[k], systems_[k]->dimension()) = systems_[k]->velocity();
  }
}

void NonSmoothDynamicalSystem::scatter_state(const VectorXd& q, const VectorXd& v) {
  for (std::size_t k = 0; k < systems_.size(); ++k)
    systems_[k]->set_state(q.segment(offsets_[k], systems_[k]->dimension()),
                           v.segment(offsets_[k], systems_[k]->dimension()));
}

void NonSmoothDynamicalSystem::stack(Index j, const VectorXd& global, VectorXd& local) const {
  const Link& link = links_[j];
  const Index first_size = systems_[link.first]->dimension();
  local.head(first_size) = global.segment(offsets_[link.first], first_size);
  if (link.second >= 0)
    local.tail(systems_[link.second]->dimension()) =
        global.segment(offsets_[link.second], systems_[link.second]->dimension());
}

double NonSmoothDynamicalSystem::gap(Index j, const VectorXd& q) const {
  Workspace& work = workspaces_[j];
  stack(j, q, work.q);
  return interactions_[j]->relation().gap(work.q);
}

double NonSmoothDynamicalSystem::velocity(Index j, const VectorXd& q, const VectorXd& v) const {
  Workspace& work = workspaces_[j];
  stack(j, q, work.q);
  stack(j, v, work.v);
  interactions_[j]->checked_jacobian(work.q, work.row);
  return work.row.dot(work.v);
}

double NonSmoothDynamicalSystem::jacobian_rate(Index j, const VectorXd& q,
                                               const VectorXd& v) const {
  Workspace& work = workspaces_[j];
  stack(j, q, work.q);
  stack(j, v, work.v);
  return interactions_[j]->relation().jacobian_rate(work.q, work.v);
}

void NonSmoothDynamicalSystem::tangent_rates(Index j, const VectorXd& q, const VectorXd& v,
                                             VectorXd& rates) const {
  Workspace& work = workspaces_[std::size_t(j)];
  stack(j, q, work.q);
  stack(j, v, work.v);
  const Relation& relation = interactions_[std::size_t(j)]->relation();
  rates.resize(relation.tangent_rows());
  relation.tangent_rates(work.q, work.v, rates);
}

Eigen::SparseMatrix<double> NonSmoothDynamicalSystem::jacobian_matrix(std::span<const Index> subset,
                                                                      const VectorXd& q) const {
  std::vector<Eigen::Triplet<double>> entries;
  for (std::size_t k = 0; k < subset.size(); ++k)
    for_each_jacobian_entry(subset[k], q, [&](Index row, double value) {
      if (value != 0.0) entries.emplace_back(row, Index(k), value);
    });
  Eigen::SparseMatrix<double> W(dof_, Index(subset.size()));
  W.setFromTriplets(entries.begin(), entries.end());
  return W;
}

Eigen::SparseMatrix<double> NonSmoothDynamicalSystem::tangent_matrix(
    std::span<const Index> subset, const VectorXd& q, std::vector<Index>& first_row) const {
  std::vector<Eigen::Triplet<double>> entries;
  first_row.assign(1, 0);
  MatrixXd rows;
  for (Index j : subset) {
    const Relation& relation = interactions_[std::size_t(j)]->relation();
    const int count = relation.tangent_rows();
    if (count > 0) {
      Workspace& work = workspaces_[std::size_t(j)];
      stack(j, q, work.q);
      rows.setZero(count, work.q.size());
      relation.tangent_jacobian(work.q, rows);
      const Link& link = links_[std::size_t(j)];
      const Index first_size = systems_[std::size_t(link.first)]->dimension();
      for (Index c = 0; c < rows.cols(); ++c) {
        const Index global = c < first_size ? offsets_[std::size_t(link.first)] + c
                                            : offsets_[std::size_t(link.second)] + (c - first_size);
        for (int r = 0; r < count; ++r)
          if (rows(r, c) != 0.0) entries.emplace_back(global, first_row.back() + r, rows(r, c));
      }
    }
    first_row.push_back(first_row.back() + count);
  }
  Eigen::SparseMatrix<double> W_t(dof_, first_row.back());
  W_t.setFromTriplets(entries.begin(), entries.end());
  return W_t;
}

Eigen::SparseMatrix<double> NonSmoothDynamicalSystem::mass_matrix(const VectorXd& q) const {
  std::vector<Eigen::Triplet<double>> entries;
  MatrixXd block;
  for (std::size_t k = 0; k < systems_.size(); ++k) {
    const Index n = systems_[k]->dimension();
    block.setZero(n, n);
    systems_[k]->mass(q.segment(offsets_[k], n), block);
    for (Index c = 0; c < n; ++c)
      for (Index r = 0; r < n; ++r)
        if (block(r, c) != 0.0) entries.emplace_back(offsets_[k] + r, offsets_[k] + c, block(r, c));
  }
  Eigen::SparseMatrix<double> M(dof_, dof_);
  M.setFromTriplets(entries.begin(), entries.end());
  return M;
}

void NonSmoothDynamicalSystem::check(double penetration_tolerance) const {
  for (const auto& system : systems_) system->check_mass();
  for (const auto& interaction : interactions_) {
    const double g = interaction->gap();
    if (!(g >= -penetration_tolerance))
      throw InvalidInput("interaction '" + interaction->name() + "' starts interpenetrated: " +
                         invalid_value_message("gap", g,
                                               "gap >= -" + to_text(penetration_tolerance) +
                                                   " (the penetration tolerance, m)"));
  }
}

}  // namespace mimpact::kernel
