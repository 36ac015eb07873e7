#pragma once

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "mimpact/granular/contact_model.hpp"
#include "mimpact/granular/impact_outcome.hpp"
#include "mimpact/granular/moving_contacts_stats.hpp"
#include "mimpact/granular/progress_meter.hpp"
#include "mimpact/granular/run_limits.hpp"
#include "mimpact/granular/scene_spec.hpp"
#include "mimpact/granular/time_series.hpp"
#include "mimpact/kernel/non_smooth_dynamical_system.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"

// The impact runs every granular scene shares (chains and packings): through the kernel, by the
// LZB impact problem in the event-driven scheme or by the compliant contacts integrated in time,
// and the energy ledger of their outcome.
namespace mimpact::granular {

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

// What a compliant run records and reports beside its outcome.
struct CompliantRunOptions {
  RecordSpec record;    // the contacts and bodies sampled, every record.interval
  int frame_every = 0;  // every frame_every-th sample a frame of the whole scene (0: none)
  RunLimits limits;     // the memory the samples and frames may take
  ProgressMeter* progress = nullptr;
};

// The impact computed with the compliant contacts integrated in time (method "compliant"): the
// same outcome fields (impulses, peaks and their times from the first contact; steps are the
// integration's), the recorded time series and frames, within the memory of options.limits
// (InvalidInput before the run when the samples of the impact's shortest possible duration
// would exceed it, and during it when they do).
CompliantRun simulate_compliant(const ContactModel& model,
                                std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                                const CompliantSpec& spec, const CompliantRunOptions& options = {});

}  // namespace mimpact::granular
