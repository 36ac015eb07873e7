#pragma once

#include <Eigen/Dense>
#include <vector>

#include "mimpact/numerics/impact_integrator.hpp"

// The outcome of a granular scene's impacts, whichever run computed it (impact_runs.hpp).
namespace mimpact::granular {

// The outcome of a scene's impacts: the strikers fly to their targets (if there are gaps), the
// shock crosses the touching beads; with strikers arriving at different times, one impact after
// the other. Per-contact results are summed (impulses, steps) or taken at their peak over all
// impacts, times counted from the first impact.
// The contacts a run that moves the bodies formed beyond the model's (the moving geometry's
// meetings): how many, what they dissipated (their turns' losses and slip work) and what they
// hold at the end (J).
struct FormedContacts {
  Eigen::Index count = 0;
  double dissipated = 0.0;
  double potential_left = 0.0;
};

struct ImpactOutcome {
  // the impacts' result, aggregated, whichever method computed it (the LZB integrators or the
  // compliant contacts): per contact the impulse, peak force and its time, work and stored
  // energy; the steps and duration
  numerics::ImpactResult result;
  Eigen::VectorXd velocity_after;  // per coordinate (m/s), after the last impact
  // rad/s, components per body, after the last impact: when the bodies turn (else empty)
  Eigen::VectorXd angular_velocity_after;
  // per coordinate (m): where a run that moves the bodies (the compliant contacts in the moving
  // geometry) left them; empty where the impact finds them fixed
  Eigen::VectorXd position_after;
  double impact_time = 0.0;  // s, when the first impact began
  double wall_time = 0.0;    // s spent in the impact computations
  // compliant method, free scene: compliant.end_time came with contacts still closed, so the
  // velocities are those at that time, not the final ones (summary status "end_time")
  bool cut_by_end_time = false;
  // the energy ledger beyond lzb.work and lzb.stored_energy (J): the contacts' potential
  // energy at the start (a precompression's) and the work of the bodies' own forces
  Eigen::VectorXd stored_energy_at_start;
  double work_of_forces = 0.0;
  FormedContacts formed;
  // per impact, in order: when it began (s) and the coordinates' velocities just before it
  std::vector<double> impact_times;
  std::vector<Eigen::VectorXd> velocities_before;
  // per impact, when the bodies turn: their angular velocities just before it (rad/s)
  std::vector<Eigen::VectorXd> angular_velocities_before;
};

}  // namespace mimpact::granular
