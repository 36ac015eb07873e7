#include "mimpact/plugins/acceleration_lcp_problem.hpp"

#include <limits>

#include "contact_dynamics.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::plugins {

AccelerationLcpProblem::AccelerationLcpProblem(numerics::LemkeOptions options) : options_(options) {
  validate(options_, "acceleration-lcp");
}

AccelerationLcpProblem::~AccelerationLcpProblem() = default;

namespace {

// A contact held closed with a force while its points slip needs Coulomb's law in the smooth
// motion, which the acceleration-level problem does not have yet: an error naming the contact,
// rather than a frictionless slide. A contact that rubs without slipping (at rest, rolling) or
// without force is what a frictionless contact does.
void refuse_sliding_with_friction(const kernel::NonSmoothDynamicalSystem& system,
                                  std::span<const Index> persistent, const VectorXd& force,
                                  double time, const VectorXd& q, const VectorXd& v) {
  const double resolution = 1e-9 * v.cwiseAbs().maxCoeff();  // m/s
  for (std::size_t k = 0; k < persistent.size(); ++k) {
    const kernel::Interaction& contact = system.interaction(persistent[k]);
    const auto* law = dynamic_cast<const LzbLaw*>(&contact.law());
    const double mu = law ? law->contact_law().friction : 0.0;
    if (!(mu > 0.0) || !(force(Index(k)) > 0.0) || contact.relation().tangent_rows() == 0) continue;
    std::vector<Index> first_row;
    const Index one[] = {persistent[k]};
    const double slip = (system.tangent_matrix(one, q, first_row).transpose() * v).norm();
    if (slip > resolution)
      throw Error("interaction '" + contact.name() + "' (friction = " + to_text(mu) +
                  ") slides at " + to_text(slip) + " m/s while held closed by " +
                  to_text(force(Index(k))) + " N at t = " + to_text(time) +
                  " s: the event-driven scheme holds a contact with friction only while it does "
                  "not slip (Coulomb's law in the acceleration-level problem is not there yet); "
                  "the compliant integrator rubs it");
  }
}

}  // namespace

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
  if (forces.solved) refuse_sliding_with_friction(system, persistent, forces.force, time, q, v);
  if (!forces.solved)
    forces.message =
        "Lemke: " + std::string(numerics::to_string(result.status)) + ": " + result.message;
  return forces;
}

}  // namespace mimpact::plugins
