#pragma once

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "mimpact/granular/contact_model.hpp"
#include "mimpact/granular/moving_contacts.hpp"
#include "mimpact/granular/run_limits.hpp"
#include "mimpact/granular/scene_spec.hpp"
#include "mimpact/granular/time_series.hpp"
#include "mimpact/kernel/non_smooth_dynamical_system.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"

// The impact runs every granular scene shares (chains and planar packings): through the kernel,
// by the LZB impact problem in the event-driven scheme or by the compliant contacts integrated
// in time, and the energy ledger of their outcome.
namespace mimpact::granular {

// The outcome of a scene's impacts: the strikers fly to their targets (if there are gaps), the
// shock crosses the touching beads; with strikers arriving at different times, one impact after
// the other. Per-contact results are summed (impulses, steps) or taken at their peak over all
// impacts, times counted from the first impact.
struct ImpactOutcome {
  // the impacts' result, aggregated, whichever method computed it (the LZB integrators or the
  // compliant contacts): per contact the impulse, peak force and its time, work and stored
  // energy; the steps and duration
  numerics::LzbResult result;
  Eigen::VectorXd velocity_after;  // per coordinate (m/s), after the last impact
  double impact_time = 0.0;        // s, when the first impact began
  double wall_time = 0.0;          // s spent in the impact computations
  // compliant method, free scene: compliant.end_time came with contacts still closed, so the
  // velocities are those at that time, not the final ones (summary status "end_time")
  bool cut_by_end_time = false;
  // the energy ledger beyond lzb.work and lzb.stored_energy (J): the contacts' potential
  // energy at the start (a precompression's) and the work of the bodies' own forces
  Eigen::VectorXd stored_energy_at_start;
  double work_of_forces = 0.0;
  // per impact, in order: when it began (s) and the coordinates' velocities just before it
  std::vector<double> impact_times;
  std::vector<Eigen::VectorXd> velocities_before;
};

// Through the kernel: `system` (body b is the model's body b), the event-driven integrator, the
// LZB impact problem; the run ends with the impact of the last striker to arrive. `observer`
// sees the samples of every impact (as `options` says) with the model's contact indices.
ImpactOutcome simulate_impacts(const ContactModel& model,
                               std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                               const plugins::LzbImpactOptions& options,
                               numerics::ImpactObserver* observer = nullptr);

// The same impact on numerics alone (H of the model, no kernel), for comparisons: zero gaps
// only.
ImpactOutcome simulate_impact_numerics(const ContactModel& model,
                                       const numerics::LzbOptions& options,
                                       numerics::ImpactObserver* observer = nullptr);

struct CompliantRun {
  ImpactOutcome impact;
  TimeSeries series;
  Frames frames;  // every frame_every outputs, when asked for
  // the most bodies integrated at once: the others flew in closed form
  Eigen::Index most_bodies_in_motion = 0;
  MovingContactsStats moving;  // the moving geometry's counts (zero in the frozen one)
};

// The impact computed with the compliant contacts integrated in time (method "compliant"): the
// same outcome fields (impulses, peaks and their times from the first contact; steps are the
// integration's), the recorded time series, sampled every record.interval, and every
// frame_every-th sample a frame of the whole scene (0: none), within the memory of `limits`
// (InvalidInput before the run when the samples of the impact's shortest possible duration
// would exceed it, and during it when they do).
CompliantRun simulate_compliant(const ContactModel& model,
                                std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                                const CompliantSpec& spec, const RecordSpec& record,
                                int frame_every = 0, const RunLimits& limits = {});

}  // namespace mimpact::granular
