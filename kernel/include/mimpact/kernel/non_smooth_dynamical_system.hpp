#pragma once

#include <Eigen/SparseCore>
#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

#include "mimpact/kernel/dynamical_system.hpp"
#include "mimpact/kernel/interaction.hpp"

namespace mimpact::kernel {

// The index sets of Nguyen & Brogliato (2011), algorithm 5: interactions by index into the system.
struct IndexSets {
  std::vector<Index> closed;      // I_c: gap within tolerance of 0
  std::vector<Index> persistent;  // I_s, part of I_c: closed, u = 0, held by contact forces
};

// Dynamical systems and the interactions between them. The systems' coordinates are laid
// end to end in one global vector (system k at offset(k)); interactions are evaluated on
// global vectors without allocating, through per-interaction workspaces.
class NonSmoothDynamicalSystem {
 public:
  Index add(std::shared_ptr<DynamicalSystem> system);
  // Throws InvalidInput when a system of the interaction has not been added.
  Index add(std::shared_ptr<Interaction> interaction);

  Index system_count() const { return Index(systems_.size()); }
  Index interaction_count() const { return Index(interactions_.size()); }
  DynamicalSystem& system(Index k) { return *systems_[k]; }
  const DynamicalSystem& system(Index k) const { return *systems_[k]; }
  const Interaction& interaction(Index j) const { return *interactions_[j]; }
  Index dof() const { return dof_; }
  Index offset(Index system) const { return offsets_[system]; }
  // the systems of interaction j; the second is -1 for a contact with the ground
  Index first_system(Index j) const { return links_[j].first; }
  Index second_system(Index j) const { return links_[j].second; }
  // the interactions that touch system k
  const std::vector<Index>& interactions_of(Index k) const { return touching_[k]; }

  bool has_force() const;         // some system has a force
  bool mass_is_diagonal() const;  // every mass matrix is diagonal
  bool mass_is_constant() const;

  void gather_state(VectorXd& q, VectorXd& v) const;
  void scatter_state(const VectorXd& q, const VectorXd& v);

  // Interaction j evaluated on global q (and v).
  double gap(Index j, const VectorXd& q) const;
  double velocity(Index j, const VectorXd& q, const VectorXd& v) const;
  double jacobian_rate(Index j, const VectorXd& q, const VectorXd& v) const;
  // Calls visit(global index, value) for each entry of W_j = dg_j/dq.
  template <class Visit>
  void for_each_jacobian_entry(Index j, const VectorXd& q, Visit&& visit) const;
  // W restricted to `subset`: dof() x subset.size(), column k for interaction subset[k].
  Eigen::SparseMatrix<double> jacobian_matrix(std::span<const Index> subset,
                                              const VectorXd& q) const;
  // The tangent rows of `subset`'s relations (Relation::tangent_jacobian): dof() x rows, the
  // rows of subset[k] from first_row[k] (subset.size() + 1 offsets, written here).
  Eigen::SparseMatrix<double> tangent_matrix(std::span<const Index> subset, const VectorXd& q,
                                             std::vector<Index>& first_row) const;
  // (dW_t/dt)^T v of interaction j's tangent rows (Relation::tangent_rates), resized here.
  void tangent_rates(Index j, const VectorXd& q, const VectorXd& v, VectorXd& rates) const;
  // The block-diagonal global mass matrix at q.
  Eigen::SparseMatrix<double> mass_matrix(const VectorXd& q) const;

  IndexSets& index_sets() { return index_sets_; }
  const IndexSets& index_sets() const { return index_sets_; }

  // Throws InvalidInput naming the first system whose mass is not positive definite, or the
  // first interaction whose gap is below -penetration_tolerance (interpenetration).
  void check(double penetration_tolerance) const;

 private:
  struct Link {
    Index first = -1, second = -1;
  };
  struct Workspace {
    VectorXd q, v;
    RowVectorXd row;
  };
  void stack(Index j, const VectorXd& global, VectorXd& local) const;

  std::vector<std::shared_ptr<DynamicalSystem>> systems_;
  std::vector<std::shared_ptr<Interaction>> interactions_;
  std::unordered_map<const DynamicalSystem*, Index> index_of_;
  std::vector<Index> offsets_;
  std::vector<Link> links_;
  std::vector<std::vector<Index>> touching_;
  mutable std::vector<Workspace> workspaces_;
  Index dof_ = 0;
  IndexSets index_sets_;
};

template <class Visit>
void NonSmoothDynamicalSystem::for_each_jacobian_entry(Index j, const VectorXd& q,
                                                       Visit&& visit) const {
  Workspace& work = workspaces_[j];
  stack(j, q, work.q);
  interactions_[j]->checked_jacobian(work.q, work.row);
  const Link& link = links_[j];
  const Index first_size = systems_[link.first]->dimension();
  for (Index k = 0; k < first_size; ++k) visit(offsets_[link.first] + k, work.row[k]);
  if (link.second >= 0)
    for (Index k = 0; k < systems_[link.second]->dimension(); ++k)
      visit(offsets_[link.second] + k, work.row[first_size + k]);
}

}  // namespace mimpact::kernel
