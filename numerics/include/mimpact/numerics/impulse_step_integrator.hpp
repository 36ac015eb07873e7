#pragma once

#include <Eigen/Dense>

#include "mimpact/numerics/impact_integrator.hpp"
#include "mimpact/numerics/lzb_options.hpp"

namespace mimpact::numerics {

// The impulse an impact needs to stop its fastest contact alone, max_j max(-u_j-, 0) / H_jj
// (N s): the scale relative_delta_p is a share of. 0 when no contact approaches.
double natural_impulse(const Eigen::VectorXd& diagonal, const Eigen::VectorXd& u_minus);

// The integrators that take steps of the principal impulse, synchronous or asynchronous: their
// options, the step delta_p (fixed, or resolved impact by impact from relative_delta_p where H
// and u- are known) and what that step resolves.
class ImpulseStepIntegrator : public ImpactIntegrator {
 public:
  // The options, delta_p that of the last impact when relative_delta_p is set.
  const LzbOptions& options() const { return options_; }
  // Sets the principal step (N s) of the next impacts, relative_delta_p unset. Throws
  // InvalidInput unless it is finite and > 0.
  void set_delta_p(double delta_p);
  // tol_u_j = termination_velocity_factor H_jj delta_p for this impact's delta_p, or the fixed
  // threshold.
  Eigen::VectorXd velocity_resolution(const Eigen::VectorXd& diagonal,
                                      const Eigen::VectorXd& u_minus) const override;

 protected:
  // Throws InvalidInput naming an option out of range.
  explicit ImpulseStepIntegrator(LzbOptions options);

  // Sets this impact's delta_p, then takes its steps (take_steps).
  void run(const Input& input, ImpactObserver* observer, ImpactResult& result) final;
  virtual void take_steps(const Input& input, ImpactObserver* observer, ImpactResult& result) = 0;

 private:
  double impact_delta_p(const Eigen::VectorXd& diagonal, const Eigen::VectorXd& u_minus) const;

  LzbOptions options_;
};

}  // namespace mimpact::numerics
