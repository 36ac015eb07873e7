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
  }
}

ImpactResult ImpactIntegrator::integrate(const Eigen::SparseMatrix<double>& H,
                                         const Eigen::VectorXd& u_minus,
                                         std::span<const ContactLaw> laws,
                                         ImpactObserver* observer) {
  if (H.isCompressed()) return integrate_checked(H, u_minus, laws, nullptr, observer);
  Eigen::SparseMatrix<double> compressed = H;
  compressed.makeCompressed();
  return integrate_checked(compressed, u_minus, laws, nullptr, observer);
}

ImpactResult ImpactIntegrator::integrate(const Eigen::MatrixXd& H, const Eigen::VectorXd& u_minus,
                                         std::span<const ContactLaw> laws,
                                         ImpactObserver* observer) {
  checked_impact_input(H, u_minus, laws, sampled_contacts_);  // the dense matrix's own messages
  Eigen::SparseMatrix<double> sparse = H.sparseView(0.0, 0.0);
  sparse.makeCompressed();
  return integrate_checked(sparse, u_minus, laws, nullptr, observer);
}

ImpactResult ImpactIntegrator::integrate(const Delassus& delassus, const Eigen::VectorXd& u_minus,
                                         std::span<const ContactLaw> laws,
                                         ImpactObserver* observer) {
  if (delassus.H().isCompressed())
    return integrate_checked(delassus.H(), u_minus, laws, &delassus.mobility(), observer);
  Eigen::SparseMatrix<double> compressed = delassus.H();
  compressed.makeCompressed();
  return integrate_checked(compressed, u_minus, laws, &delassus.mobility(), observer);
}

ImpactResult ImpactIntegrator::integrate_checked(const Eigen::SparseMatrix<double>& H,
                                                 const Eigen::VectorXd& u_minus,
                                                 std::span<const ContactLaw> laws,
                                                 const Eigen::SparseMatrix<double>* mobility,
                                                 ImpactObserver* observer) {
  const Eigen::VectorXd diagonal = checked_impact_input(H, u_minus, laws, sampled_contacts_);
  laws_.assign(laws);
  sampler_.reset(sampled_contacts_, laws.size());
  ImpactResult result;
  run({.H = H, .diagonal = diagonal, .u_minus = u_minus, .laws = laws_, .mobility = mobility},
      observer, result);
  // u+ = u- + H P, summed column by column onto u- as the step loops apply their impulses
  result.velocity = u_minus;
  result.velocity.noalias() += H * result.impulse;
  result.residual_energy = result.stored_energy.sum();
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

}  // namespace mimpact::numerics
