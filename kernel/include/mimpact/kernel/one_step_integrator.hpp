#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "mimpact/kernel/non_smooth_dynamical_system.hpp"
#include "mimpact/kernel/one_step_ns_problem.hpp"

namespace mimpact::kernel {

// What one advance of the integrator did.
struct StepReport {
  double time = 0.0;             // where it stopped
  bool event = false;            // a nonsmooth event was processed at `time`
  std::vector<Index> closing;    // contacts whose gap reached 0
  std::vector<Index> detaching;  // persistent contacts whose force reached 0
  std::optional<ImpactReport> impact;
  // the forces of the persistent contacts, when they were decided at the start of this advance
  std::optional<ContactForces> contact_forces;
  std::int64_t smooth_steps = 0;  // steps of the smooth integration
};

// Moves the system through time: smooth motion between nonsmooth events, which it locates
// and processes with the problems it is given (Siconos's OneStepIntegrator, for an
// event-driven scheme).
class OneStepIntegrator {
 public:
  virtual ~OneStepIntegrator() = default;
  virtual std::string_view name() const = 0;
  // Called once before a run, with the system at time `start`.
  virtual void initialize(NonSmoothDynamicalSystem& system, double start, ImpactProblem& impacts,
                          ContactForceProblem& forces) = 0;
  // Advances from the current time to `target`, or to the first nonsmooth event before it,
  // which it processes. Leaves the systems' states at the time reached.
  virtual StepReport advance(double target) = 0;
  virtual double time() const = 0;
};

}  // namespace mimpact::kernel
