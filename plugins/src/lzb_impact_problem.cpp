#include "mimpact/plugins/lzb_impact_problem.hpp"

#include <algorithm>
#include <chrono>
#include <optional>

#include "mimpact/common/error.hpp"
#include "mimpact/numerics/delassus.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::plugins {

using kernel::Index;

namespace {

LzbImpactOptions checked(LzbImpactOptions options) {
  options.check("impact problem \"lzb\"");
  return options;
}

}  // namespace

LzbImpactProblem::LzbImpactProblem(LzbImpactOptions options)
    : options_(checked(std::move(options))), integrator_(make_impact_integrator(options_)) {}

void LzbImpactProblem::check_law(const kernel::NonSmoothLaw& law, const std::string& which) const {
  const auto* lzb = dynamic_cast<const LzbLaw*>(&law);
  if (!lzb)
    throw InvalidInput("interaction '" + which + "' has a \"" + std::string(law.kind()) +
                       "\" law, which the \"lzb\" impact problem cannot handle; allowed: "
                       "plugins::LzbLaw");
  if (const double ratio = lzb->contact_law().tangential_stiffness_ratio; ratio != 0.0)
    throw InvalidInput(invalid_value_message(
        "tangential_stiffness_ratio", ratio,
        "0 in the LZB impact (interaction '" + which +
            "'), whose tangential response is rigid (Coulomb's law alone); the compliant "
            "integrator takes a Mindlin spring"));
}

namespace {

// Hands the samples on with the contacts named by their interaction in the system, not by
// their place among the closed contacts of this impact.
class InteractionSamples : public numerics::ImpactObserver {
 public:
  InteractionSamples(std::span<const Index> closed, numerics::ImpactObserver& next)
      : closed_(closed), next_(next) {}
  void observe(const numerics::ImpactSample& sample) override {
    interactions_.resize(sample.contacts.size());
    for (std::size_t k = 0; k < sample.contacts.size(); ++k)
      interactions_[k] = closed_[std::size_t(sample.contacts[k])];
    numerics::ImpactSample renamed = sample;
    renamed.contacts = interactions_;
    next_.observe(renamed);
  }
  void progressed(const numerics::ImpactProgress& where) override { next_.progressed(where); }

 private:
  std::span<const Index> closed_;
  numerics::ImpactObserver& next_;
  std::vector<Index> interactions_;
};

// The places among `closed` of the sampled interactions that take part.
std::vector<Index> sampled_places(std::span<const Index> closed,
                                  const std::vector<Index>& sampled) {
  std::vector<Index> places;
  for (std::size_t k = 0; k < closed.size(); ++k)
    if (std::find(sampled.begin(), sampled.end(), closed[k]) != sampled.end())
      places.push_back(Index(k));
  return places;
}

// Every closed interaction with friction has tangent rows (Relation::tangent_rows).
void check_tangents(const kernel::NonSmoothDynamicalSystem& system, std::span<const Index> closed,
                    const std::vector<numerics::ContactLaw>& laws) {
  for (std::size_t k = 0; k < closed.size(); ++k)
    if (laws[k].friction > 0.0 && system.interaction(closed[k]).relation().tangent_rows() == 0)
      throw InvalidInput("interaction '" + system.interaction(closed[k]).name() + "': " +
                         invalid_value_message("friction", laws[k].friction,
                                               "0 for a relation without tangent rows (give "
                                               "them: Relation::tangent_rows)"));
}

}  // namespace

// The impact with Coulomb friction: H, H_tn and H_tt from one Delassus operator of the normal
// and tangent columns [W W_t], and v+ = v- + M^-1 (W P + W_t P_t).
void LzbImpactProblem::solve_with_friction(const kernel::NonSmoothDynamicalSystem& system,
                                           std::span<const Index> closed, const Eigen::VectorXd& q,
                                           const Eigen::SparseMatrix<double>& W,
                                           numerics::ImpactObserver* observer,
                                           kernel::ImpactReport& report) {
  numerics::TangentialRows rows;
  const Eigen::SparseMatrix<double> W_t = system.tangent_matrix(closed, q, rows.first_row);
  const Index m = W.cols(), r = W_t.cols();
  Eigen::SparseMatrix<double> columns(W.rows(), m + r);
  columns.leftCols(m) = W;
  columns.rightCols(r) = W_t;
  const numerics::Delassus delassus =
      system.mass_is_diagonal()
          ? numerics::Delassus(columns, system.mass_matrix(q).diagonal().cwiseInverse())
          : numerics::Delassus(columns, system.mass_matrix(q));
  const Eigen::SparseMatrix<double> H = delassus.H().topLeftCorner(m, m);
  rows.normal_to_tangent = delassus.H().bottomLeftCorner(r, m);
  rows.tangent = delassus.H().bottomRightCorner(r, r);
  rows.slip_minus = W_t.transpose() * report.generalized_velocity_before;
  const Eigen::VectorXd& u_minus = report.velocity_before;
  report.result = integrator_->integrate(H, u_minus, laws_, rows, observer);
  report.velocity_resolution =
      integrator_->velocity_resolution(Eigen::VectorXd(H.diagonal()), u_minus);
  Eigen::VectorXd impulses(m + r);
  impulses << report.result.impulse, report.result.tangential_impulse;
  report.generalized_velocity_after =
      report.generalized_velocity_before + delassus.mobility() * impulses;
}

kernel::ImpactReport LzbImpactProblem::solve(kernel::NonSmoothDynamicalSystem& system,
                                             std::span<const Index> closed, double time) {
  const auto start = std::chrono::steady_clock::now();
  kernel::ImpactReport report;
  Eigen::VectorXd q;
  system.gather_state(q, report.generalized_velocity_before);
  laws_.clear();
  for (Index j : closed)
    laws_.push_back(static_cast<const LzbLaw&>(system.interaction(j).law()).contact_law());

  const Eigen::SparseMatrix<double> W = system.jacobian_matrix(closed, q);
  const bool frictional =
      std::any_of(laws_.begin(), laws_.end(),
                  [](const numerics::ContactLaw& law) { return law.friction > 0.0; });
  std::optional<InteractionSamples> samples;
  if (observer_) {
    samples.emplace(closed, *observer_);
    const std::vector<Index>& sampled = options_.impulse_steps.sampled_contacts;
    if (!sampled.empty()) integrator_->set_sampled_contacts(sampled_places(closed, sampled));
  }
  numerics::ImpactObserver* observer = samples ? &*samples : nullptr;
  report.velocity_before = W.transpose() * report.generalized_velocity_before;
  const Eigen::VectorXd& u_minus = report.velocity_before;
  if (frictional) {
    check_tangents(system, closed, laws_);
    solve_with_friction(system, closed, q, W, observer, report);
  } else {
    const numerics::Delassus delassus =
        system.mass_is_diagonal()
            ? numerics::Delassus(W, system.mass_matrix(q).diagonal().cwiseInverse())
            : numerics::Delassus(W, system.mass_matrix(q));
    report.result = integrator_->integrate(delassus, u_minus, laws_, observer);
    report.velocity_resolution =
        integrator_->velocity_resolution(Eigen::VectorXd(delassus.H().diagonal()), u_minus);
    report.generalized_velocity_after =
        report.generalized_velocity_before + delassus.mobility() * report.result.impulse;
  }
  report.time = time;
  report.interactions.assign(closed.begin(), closed.end());
  if (report.result.status == numerics::ImpactStatus::terminated) {
    system.scatter_state(q, report.generalized_velocity_after);
  } else {
    report.generalized_velocity_after = report.generalized_velocity_before;  // no outcome
  }
  report.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace mimpact::plugins
