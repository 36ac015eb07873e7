#include "mimpact/numerics/impact_integrator.hpp"

#include <cmath>

#include "impact_input.hpp"
#include "mimpact/common/error.hpp"

namespace mimpact::numerics {

std::string_view to_string(ImpactStatus status) {
  return status == ImpactStatus::terminated ? "terminated" : "step_limit";
}

void LawTable::assign(std::span<const ContactLaw> laws) {
  rows_.resize(laws.size());
  friction_.resize(laws.size());
  frictional_ = false;
  for (std::size_t j = 0; j < laws.size(); ++j) {
    const ContactLaw& law = laws[j];
    const double e = law.effective_restitution();
    rows_[j] = {.coefficient = law.force_coefficient(),
                .power = law.exponent / (1.0 + law.exponent),
                .one_plus_exponent = 1.0 + law.exponent,
                .stiffness = law.stiffness,
                .exponent = law.exponent,
                .restitution = e,
                .inverse_e2 = e > 0.0 ? 1.0 / (e * e) : 0.0,
                .mono_stiffness = law.model == ComplianceModel::mono_stiffness};
    friction_[j] = law.friction;
    frictional_ = frictional_ || law.friction > 0.0;
  }
}

ImpactResult ImpactIntegrator::integrate(const Eigen::SparseMatrix<double>& H,
                                         const Eigen::VectorXd& u_minus,
                                         std::span<const ContactLaw> laws,
                                         ImpactObserver* observer) {
  if (H.isCompressed()) return integrate_checked({H, u_minus, laws}, observer);
  Eigen::SparseMatrix<double> compressed = H;
  compressed.makeCompressed();
  return integrate_checked({compressed, u_minus, laws}, observer);
}

ImpactResult ImpactIntegrator::integrate(const Eigen::MatrixXd& H, const Eigen::VectorXd& u_minus,
                                         std::span<const ContactLaw> laws,
                                         ImpactObserver* observer) {
  checked_impact_input(H, u_minus, laws, sampled_contacts_);  // the dense matrix's own messages
  Eigen::SparseMatrix<double> sparse = H.sparseView(0.0, 0.0);
  sparse.makeCompressed();
  return integrate_checked({sparse, u_minus, laws}, observer);
}

ImpactResult ImpactIntegrator::integrate(const Delassus& delassus, const Eigen::VectorXd& u_minus,
                                         std::span<const ContactLaw> laws,
                                         ImpactObserver* observer) {
  if (delassus.H().isCompressed())
    return integrate_checked({delassus.H(), u_minus, laws, &delassus.mobility()}, observer);
  Eigen::SparseMatrix<double> compressed = delassus.H();
  compressed.makeCompressed();
  return integrate_checked({compressed, u_minus, laws, &delassus.mobility()}, observer);
}

ImpactResult ImpactIntegrator::integrate(const Eigen::SparseMatrix<double>& H,
                                         const Eigen::VectorXd& u_minus,
                                         std::span<const ContactLaw> laws,
                                         const TangentialRows& tangential,
                                         ImpactObserver* observer) {
  Eigen::SparseMatrix<double> compressed = H;
  compressed.makeCompressed();
  return integrate_checked({compressed, u_minus, laws, nullptr, &tangential}, observer);
}

ImpactResult ImpactIntegrator::integrate_checked(const Given& given, ImpactObserver* observer) {
  const Eigen::VectorXd diagonal =
      checked_impact_input(given.H, given.u_minus, given.laws, sampled_contacts_);
  checked_friction(given.laws, given.tangential, integrates_friction(), name());
  Eigen::SparseMatrix<double> tangent_to_normal;
  if (given.tangential) {
    tangent_to_normal = given.tangential->normal_to_tangent.transpose();
    tangent_to_normal.makeCompressed();
  }
  laws_.assign(given.laws);
  sampler_.reset(sampled_contacts_, given.laws.size(),
                 laws_.frictional() ? given.tangential : nullptr);
  ImpactResult result;
  run({.H = given.H,
       .diagonal = diagonal,
       .u_minus = given.u_minus,
       .laws = laws_,
       .mobility = given.mobility,
       .tangential = given.tangential,
       .tangent_to_normal = given.tangential ? &tangent_to_normal : nullptr},
      observer, result);
  assemble(given, &tangent_to_normal, result);
  // finite inputs can still overflow (an exponent of 1e3 puts E^(eta/(1+eta)) past double)
  const bool finite_time = std::isfinite(result.duration);
  if (!(finite_time && result.velocity.allFinite() && result.max_force.allFinite()))
    throw Error("the impact's " + std::string(finite_time ? "velocities or forces" : "duration") +
                " overflowed double precision after " + std::to_string(result.steps) +
                " steps of the " + std::string(name()) +
                " integrator; the contact laws' stiffness K and exponent eta are out of the range "
                "it resolves");
  return result;
}

// u+ = u- + H P (+ H_tn^T P_t), summed column by column onto u- as the step loops apply their
// impulses; with tangential rows s+ = s- + H_tn P + H_tt P_t.
void ImpactIntegrator::assemble(const Given& given,
                                const Eigen::SparseMatrix<double>* tangent_to_normal,
                                ImpactResult& result) const {
  result.velocity = given.u_minus;
  result.velocity.noalias() += given.H * result.impulse;
  result.residual_energy = result.stored_energy.sum();
  if (!given.tangential) return;
  const TangentialRows& rows = *given.tangential;
  const Eigen::Index m = given.u_minus.size();
  if (result.tangential_impulse.size() == 0)  // no friction integrated: P_t = 0
    result.tangential_impulse = Eigen::VectorXd::Zero(rows.rows());
  if (result.slip_work.size() == 0) result.slip_work = Eigen::VectorXd::Zero(m);
  result.velocity.noalias() += *tangent_to_normal * result.tangential_impulse;
  result.slip = rows.slip_minus;
  result.slip.noalias() += rows.normal_to_tangent * result.impulse;
  result.slip.noalias() += rows.tangent * result.tangential_impulse;
}

}  // namespace mimpact::numerics
