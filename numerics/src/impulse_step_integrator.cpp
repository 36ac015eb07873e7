#include "mimpact/numerics/impulse_step_integrator.hpp"

#include <cmath>
#include <string>
#include <utility>

#include "mimpact/common/error.hpp"

namespace mimpact::numerics {

double LzbOptions::velocity_tolerance(double h_jj) const {
  return fixed_thresholds ? fixed_thresholds->velocity
                          : termination_velocity_factor * h_jj * delta_p;
}

double LzbOptions::energy_tolerance(double h_jj) const {
  if (fixed_thresholds) return fixed_thresholds->energy;
  const double velocity = velocity_tolerance(h_jj);
  return velocity * velocity / (2.0 * h_jj);
}

double natural_impulse(const Eigen::VectorXd& diagonal, const Eigen::VectorXd& u_minus) {
  return (-u_minus).cwiseMax(0.0).cwiseQuotient(diagonal).maxCoeff();
}

ImpulseStepIntegrator::ImpulseStepIntegrator(LzbOptions options)
    : ImpactIntegrator(options.sampled_contacts), options_(std::move(options)) {
  validate(options_, "LZB options");
}

void ImpulseStepIntegrator::set_delta_p(double delta_p) {
  LzbOptions changed = options_;
  changed.delta_p = delta_p;
  changed.relative_delta_p.reset();
  validate(changed, "LZB options");
  options_ = std::move(changed);
}

double ImpulseStepIntegrator::impact_delta_p(const Eigen::VectorXd& diagonal,
                                             const Eigen::VectorXd& u_minus) const {
  if (!options_.relative_delta_p) return options_.delta_p;
  const double natural = natural_impulse(diagonal, u_minus);
  if (!(natural > 0.0)) return options_.delta_p;
  const double delta_p = *options_.relative_delta_p * natural;
  if (!(delta_p > 0.0 && std::isfinite(delta_p)))
    throw InvalidInput("relative_delta_p = " + to_text(*options_.relative_delta_p) +
                       " of the impact's natural impulse " + to_text(natural) +
                       " N s gives delta_p = " + to_text(delta_p) +
                       " N s; allowed: a finite delta_p > 0");
  return delta_p;
}

Eigen::VectorXd ImpulseStepIntegrator::velocity_resolution(const Eigen::VectorXd& diagonal,
                                                           const Eigen::VectorXd& u_minus) const {
  LzbOptions impact = options_;
  impact.delta_p = impact_delta_p(diagonal, u_minus);
  return diagonal.unaryExpr([&impact](double h_jj) { return impact.velocity_tolerance(h_jj); });
}

void ImpulseStepIntegrator::run(const Input& input, ImpactObserver* observer,
                                ImpactResult& result) {
  options_.delta_p = impact_delta_p(input.diagonal, input.u_minus);
  take_steps(input, observer, result);
}

}  // namespace mimpact::numerics
