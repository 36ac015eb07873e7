#pragma once

// Coulomb friction in the impulse steps (docs/model.md, "Friction"): after each step's normal
// impulses dP_n are distributed, each frictional contact's tangential impulse for the step, in
// the order the contacts step. The slip s is first moved by H_tn dP_n; the impulse that stops
// the contact's slip, x = -H_tt,cc^-1 s_c, is taken where it lies within the cone
// |x| <= mu dP_n (stick, or a slip that stops within the step), else the slip's
// -mu dP_n s_c / |s_c| (Coulomb's maximal dissipation). A first-order step in delta_p, exact
// for a lone contact whose slip does not move its normal velocity (H_tn = 0).

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <span>
#include <vector>

#include "mimpact/numerics/impact_integrator.hpp"

namespace mimpact::numerics {

class ImpulseStepFriction {
 public:
  // A new impact: on when some contact's friction is > 0 (the input then has tangential rows).
  void prepare(const ImpactIntegrator::Input& input);
  bool on() const { return on_; }

  // The step of the contacts `stepping` with normal impulses step_impulse (per contact, N s):
  // their tangential impulses, s moved by H_tn dP_n + H_tt dP_t and u by H_tn^T dP_t. The
  // contacts whose u it moved are left in pushed() for the caller's joining test.
  void step(std::span<const Eigen::Index> stepping, const double* step_impulse, double* u);
  const std::vector<Eigen::Index>& pushed() const { return pushed_; }
  double tangential_impulse(Eigen::Index row) const { return impulse_[std::size_t(row)]; }
  void finish(ImpactResult& result) const;

 private:
  // contact c's slip (1 or 2 rows) into v, its size returned
  double slip_of(Eigen::Index c, double* v) const;

  bool on_ = false;
  const TangentialRows* rows_ = nullptr;
  const Eigen::SparseMatrix<double>* tangent_to_normal_ = nullptr;  // H_tn^T
  std::vector<double> mu_, slip_work_;                              // per contact
  std::vector<double> slip_, impulse_;                              // per row: s, P_t
  std::vector<Eigen::Matrix2d> inverse_block_;  // per frictional contact: H_tt,cc^-1
  // per stepping frictional contact, in order: its index, s before the step, dP_t
  struct Stepped {
    Eigen::Index contact;
    double before[2], impulse[2];
  };
  std::vector<Stepped> stepped_;
  std::vector<Eigen::Index> pushed_;
};

}  // namespace mimpact::numerics
