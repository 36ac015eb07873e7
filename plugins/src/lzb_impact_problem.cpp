#include "mimpact/plugins/lzb_impact_problem.hpp"

#include <chrono>

#include "mimpact/numerics/delassus.hpp"
#include "mimpact/numerics/error.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::plugins {

using kernel::Index;

LzbImpactProblem::LzbImpactProblem(LzbImpactOptions options)
    : options_(std::move(options)), integrator_(options_.integrator) {
  if (!(options_.relative_delta_p >= 0.0 && options_.relative_delta_p < 1.0))
    throw InvalidInput(invalid_value_message("relative_delta_p", options_.relative_delta_p,
                                             "0 (off) or a share in (0, 1)"));
  if (options_.dense_up_to < 0)
    throw InvalidInput(invalid_value_message("dense_up_to", double(options_.dense_up_to), ">= 0"));
}

std::unique_ptr<kernel::ImpactProblem> LzbImpactProblem::create(
    const kernel::Parameters& parameters) {
  parameters.allow_only("impact problem \"lzb\"",
                        {"delta_p", "relative_delta_p", "termination_velocity_factor",
                         "max_steps", "dense_up_to"});
  LzbImpactOptions options;
  options.integrator.delta_p = parameters.get("delta_p", options.integrator.delta_p);
  options.integrator.termination_velocity_factor = parameters.get(
      "termination_velocity_factor", options.integrator.termination_velocity_factor);
  options.relative_delta_p = parameters.get("relative_delta_p", options.relative_delta_p);
  options.integrator.max_steps = parameters.get_integer("max_steps", options.integrator.max_steps, 1,
                                                        std::int64_t(1) << 62);
  options.dense_up_to = Index(parameters.get_integer("dense_up_to", options.dense_up_to, 0, std::int64_t(1) << 31));
  return std::make_unique<LzbImpactProblem>(options);
}

void LzbImpactProblem::check_law(const kernel::NonSmoothLaw& law, const std::string& which) const {
  if (!dynamic_cast<const LzbLaw*>(&law))
    throw InvalidInput("interaction '" + which + "' has a \"" + std::string(law.kind()) +
                       "\" law, which the \"lzb\" impact problem cannot handle; allowed: "
                       "plugins::LzbLaw");
}

kernel::ImpactReport LzbImpactProblem::solve(kernel::NonSmoothDynamicalSystem& system,
                                             std::span<const Index> closed, double time) {
  const auto start = std::chrono::steady_clock::now();
  Eigen::VectorXd q, v;
  system.gather_state(q, v);
  laws_.clear();
  for (Index j : closed)
    laws_.push_back(static_cast<const LzbLaw&>(system.interaction(j).law()).contact_law());

  const Eigen::SparseMatrix<double> W = system.jacobian_matrix(closed, q);
  const numerics::Delassus delassus =
      system.mass_is_diagonal()
          ? numerics::Delassus(W, system.mass_matrix(q).diagonal().cwiseInverse())
          : numerics::Delassus(W, system.mass_matrix(q));
  const Eigen::VectorXd u_minus = W.transpose() * v;
  if (options_.relative_delta_p > 0.0) {
    const double natural_impulse =
        (-u_minus).cwiseMax(0.0).cwiseQuotient(Eigen::VectorXd(delassus.H().diagonal())).maxCoeff();
    if (natural_impulse > 0.0) integrator_.set_delta_p(options_.relative_delta_p * natural_impulse);
  }
  last_ = Index(closed.size()) <= options_.dense_up_to
              ? integrator_.integrate(Eigen::MatrixXd(delassus.H()), u_minus, laws_, observer_)
              : integrator_.integrate(delassus.H(), u_minus, laws_, observer_);
  if (last_.status != numerics::LzbStatus::terminated)
    throw Error("impact at t = " + to_text(time) + ": " + last_.message);

  v += delassus.mobility() * last_.impulse;
  system.scatter_state(q, v);

  kernel::ImpactReport report;
  report.time = time;
  report.interactions.assign(closed.begin(), closed.end());
  report.velocity_before = u_minus;
  report.velocity_after = last_.velocity;
  report.impulse = last_.impulse;
  report.max_force = last_.max_force;
  report.time_of_max_force = last_.time_of_max_force;
  // the integrator's termination tolerance tol_u_j
  report.velocity_resolution = delassus.H().diagonal().unaryExpr(
      [&](double h_jj) { return integrator_.options().velocity_tolerance(h_jj); });
  report.steps = last_.steps;
  report.duration = last_.duration;
  report.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace mimpact::plugins
