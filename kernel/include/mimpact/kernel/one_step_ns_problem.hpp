#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mimpact/kernel/non_smooth_dynamical_system.hpp"
#include "mimpact/numerics/impact_observer.hpp"
#include "mimpact/numerics/impact_result.hpp"

namespace mimpact::kernel {

// What solving one impact did: the integration's own result (numerics::ImpactResult: status,
// u+, P, forces, work and counts, per contact following `interactions`) and what the problem
// adds around it.
struct ImpactReport {
  double time = 0.0;                // s, when the impact happened
  std::vector<Index> interactions;  // the closed contacts taking part
  VectorXd velocity_before;         // u- (m/s)
  numerics::ImpactResult result;    // max_force empty when the law has no force history
  VectorXd velocity_resolution;     // m/s: below this |u_j| the impact cannot tell 0 apart
  // the generalized velocities of the whole system (global coordinates), v- and v+ (v- when
  // the result has no outcome)
  VectorXd generalized_velocity_before;
  VectorXd generalized_velocity_after;
  double wall_time = 0.0;  // s spent solving it
};

// Contact forces of the persistent contacts at one state: 0 <= lambda, g'' = H lambda + b >= 0,
// lambda^T g'' = 0.
struct ContactForces {
  double time = 0.0;  // s
  std::vector<Index> interactions;
  VectorXd force;         // lambda (N, or the law's unit)
  VectorXd acceleration;  // g'' (m/s^2)
  bool solved = false;
  std::string message;  // why not, when not solved
};

// A problem solved at one instant over a set of interactions (Siconos's OneStepNSProblem).
class OneStepNSProblem {
 public:
  virtual ~OneStepNSProblem() = default;
  virtual std::string_view name() const = 0;
  // Throws InvalidInput when the law of interaction `which` is not one this problem handles.
  virtual void check_law(const NonSmoothLaw& law, const std::string& which) const = 0;
};

// The velocity jump of an impact among closed contacts, some approaching.
class ImpactProblem : public OneStepNSProblem {
 public:
  // Solves the impact of `closed` at the systems' current state, sets the systems'
  // post-impact velocities and reports.
  virtual ImpactReport solve(NonSmoothDynamicalSystem& system, std::span<const Index> closed,
                             double time) = 0;
  // Sees the steps of the impacts solved from now on, for a problem that integrates an
  // impulse dynamics (none when null); the samples name interactions by their index in the
  // system. A problem without steps has nothing to show and ignores it.
  virtual void set_impact_observer(numerics::ImpactObserver*) {}
};

// The forces that keep persistent contacts closed, at acceleration level.
class ContactForceProblem : public OneStepNSProblem {
 public:
  virtual ContactForces solve(const NonSmoothDynamicalSystem& system,
                              std::span<const Index> persistent, double time, const VectorXd& q,
                              const VectorXd& v) = 0;
};

}  // namespace mimpact::kernel
