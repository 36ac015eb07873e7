#include "mimpact/plugins/acceleration_lcp_problem.hpp"

#include "contact_dynamics.hpp"
#include "mimpact/common/error.hpp"

namespace mimpact::plugins {

AccelerationLcpProblem::AccelerationLcpProblem(numerics::LemkeOptions options) : options_(options) {
  validate(options_, "acceleration-lcp");
}

AccelerationLcpProblem::~AccelerationLcpProblem() = default;

kernel::ContactForces AccelerationLcpProblem::solve(const kernel::NonSmoothDynamicalSystem& system,
                                                    std::span<const Index> persistent, double time,
                                                    const VectorXd& q, const VectorXd& v) {
  if (initialized_for_ != &system) {
    dynamics_ = std::make_unique<ContactDynamics>();
    dynamics_->initialize(system);
    initialized_for_ = &system;
  }
  kernel::ContactForces forces;
  forces.time = time;
  forces.interactions.assign(persistent.begin(), persistent.end());
  forces.solved = true;
  if (persistent.empty()) return forces;
  dynamics_->evaluate(time, q, v, persistent);
  const VectorXd& b = dynamics_->b();
  if (b.minCoeff() >= 0.0) {  // nothing pushes a contact closed: lambda = 0
    forces.force = VectorXd::Zero(b.size());
    forces.acceleration = b;
    return forces;
  }
  ++lcp_count_;
  const numerics::LemkeResult result = numerics::solve_lemke(dynamics_->H(), b, options_);
  forces.force = result.z;
  forces.acceleration = result.w;
  forces.solved = result.solved();
  if (!forces.solved)
    forces.message =
        "Lemke: " + std::string(numerics::to_string(result.status)) + ": " + result.message;
  return forces;
}

}  // namespace mimpact::plugins
