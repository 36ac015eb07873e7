#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>

// What the integration of one impact gives, whichever integrator took it (ImpactIntegrator), and
// the kernel's impact problems report it as is (kernel::ImpactReport::result).
namespace mimpact::numerics {

enum class ImpactStatus {
  terminated,  // every contact has come out of the impact
  step_limit,  // the integration stopped at its step limit before the impact ended: no outcome
};

constexpr auto enum_names(ImpactStatus) {
  using Name = std::pair<ImpactStatus, std::string_view>;
  return std::array{Name{ImpactStatus::terminated, "terminated"},
                    Name{ImpactStatus::step_limit, "step_limit"}};
}

std::string_view to_string(ImpactStatus status);

// Per-contact vectors follow the contacts of the impact.
struct ImpactResult {
  ImpactStatus status = ImpactStatus::terminated;
  Eigen::VectorXd impulse;            // P_j (N s), cumulated over the impact
  Eigen::VectorXd velocity;           // post-impact relative velocities u+ = u- + H P (m/s)
  Eigen::VectorXd max_force;          // largest force of each contact (N)
  Eigen::VectorXd time_of_max_force;  // when it occurred (s from the start of the impact)
  double residual_energy = 0.0;       // potential energy below tolerance left at the end (J)
  // The energy ledger, per contact (J): the work the contact took from the bodies, the integral
  // of -u_j dP_j, and its potential energy at the end (summing to residual_energy). Their
  // difference is what the contact dissipated. Summed over the contacts, the work is the
  // kinetic energy lost, to round-off: each step's work is the trapezoidal rule on u, exact
  // for the linear dependence of u on P (du = H dP).
  Eigen::VectorXd work;
  Eigen::VectorXd stored_energy;
  // With tangential rows (TangentialRows; empty without): P_t per row (N s), the post-impact
  // slip s+ = s- + H_tn P + H_tt P_t per row (m/s), and per contact the work of its tangential
  // impulse, the integral of -s . dP_t (J): what slip dissipated. The kinetic energy lost is
  // the sum of `work` and `slip_work`.
  Eigen::VectorXd tangential_impulse;
  Eigen::VectorXd slip;
  Eigen::VectorXd slip_work;
  std::int64_t steps = 0;          // steps taken (the integrator says which)
  std::int64_t contact_steps = 0;  // contacts updated, summed over the steps: the work
  double duration = 0.0;           // physical duration of the impact (s)
  std::string message;             // why the impact did not terminate; empty otherwise
};

}  // namespace mimpact::numerics
