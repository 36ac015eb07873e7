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

// The problems an integrator solves at nonsmooth events; null where it solves none of that
// kind (OneStepIntegrator::needs() says which it takes).
struct EventProblems {
  ImpactProblem* impacts = nullptr;
  ContactForceProblem* contact_forces = nullptr;
};

// The forces of contacts that carry force in time (compliant contacts), per interaction. The
// impulsive forces of an impact are in its ImpactReport instead.
struct ContactForceHistory {
  VectorXd force;              // N, at the current state
  VectorXd max_force;          // N, the largest since the run began
  VectorXd time_of_max_force;  // s, when it was reached
  VectorXd impulse;            // N s, the force integrated since the run began
  bool all_open = true;        // no contact closed and none approaching: the contacts are done
  // The energy ledger since the run began (J), when the integrator keeps it (linear relations):
  // per contact the work taken from the bodies (the integral of -u_j dP_j), the potential
  // energy held now and at the start; the work of the bodies' own forces. Kinetic energy now =
  // at the start + work_of_forces - sum of work; contact j dissipated work + start - now.
  VectorXd work, stored_energy, stored_energy_at_start;
  double work_of_forces = 0.0;
  // Contacts with friction (their relation's tangent rows): the tangential impulse along each
  // row since the run began (N s; columns past the contact's rows stay 0), and the work its slip
  // took (J), which is part of its `work`. Empty where no contact has friction.
  Eigen::MatrixX2d tangential_impulse;
  VectorXd slip_work;
};

// Moves the system through time: smooth motion between nonsmooth events, which it locates
// and processes with the problems it is given (Siconos's OneStepIntegrator, for an
// event-driven scheme).
class OneStepIntegrator {
 public:
  struct Needs {
    bool impacts = false;         // an ImpactProblem
    bool contact_forces = false;  // a ContactForceProblem
  };

  virtual ~OneStepIntegrator() = default;
  virtual std::string_view name() const = 0;
  // The problems initialize() must be given; a simulation refuses others.
  virtual Needs needs() const = 0;
  // Called once before a run, with the system at time `start` and the problems needs() asks.
  virtual void initialize(NonSmoothDynamicalSystem& system, double start,
                          const EventProblems& problems) = 0;
  // Advances from the current time to `target`, or to the first nonsmooth event before it,
  // which it processes. Leaves the systems' states at the time reached.
  virtual StepReport advance(double target) = 0;
  virtual double time() const = 0;
  // The forces of the contacts in time, for an integrator whose contacts carry them between
  // events; null otherwise.
  virtual const ContactForceHistory* contact_force_history() const { return nullptr; }
};

}  // namespace mimpact::kernel
