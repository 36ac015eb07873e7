#pragma once

#include <vector>

#include "mimpact/granular/contact_model.hpp"
#include "mimpact/granular/impact_outcome.hpp"
#include "mimpact/granular/run_limits.hpp"
#include "mimpact/granular/scene_spec.hpp"
#include "mimpact/granular/time_series.hpp"
#include "mimpact/numerics/impact_observer.hpp"
#include "mimpact/plugins/lzb_impact_options.hpp"

namespace mimpact::granular {

// "record.interval = 1e-07 s, record.frames = 4": what sets the number of samples, for messages.
std::string sampling_fields(const RecordSpec& record, bool by_time, int frame_every);

// Samples the LZB steps of a scene's impacts (pass it as the impact observer, with the sampling
// it asks for) and gives the time series of RecordSpec once the run is over, and every
// frame_every-th sample a frame of the whole scene (0: none). What it keeps stays within the
// memory of `limits`: refused before the run by estimate (configure), the run stopped if the
// estimate fell short.
class ImpactRecorder : public numerics::ImpactObserver {
 public:
  ImpactRecorder(const ContactModel& model, RecordSpec record, int frame_every = 0,
                 const RunLimits& limits = {});

  // The sampling it needs: every record.every impulse steps or record.interval seconds of
  // the adaptive integration, these interactions (the recorded contacts and the ones touching
  // recorded bodies, whose impulses give the bodies' velocities; all of them for frames).
  // Throws InvalidInput when the samples it would take at the least (the impulse steps'
  // largest momentum over delta_p, or the adaptive integration's shortest compression over the
  // interval) exceed the limits.
  void configure(plugins::LzbImpactOptions& options);
  void observe(const numerics::ImpactSample& sample) override;
  TimeSeries series(const ImpactOutcome& impact) const;
  Frames frames(const ImpactOutcome& impact) const;

 private:
  struct Sample {
    std::size_t impact;
    double time;                     // s since that impact began
    std::vector<double> force;       // recorded contacts, or all of them in a frame
    std::vector<double> impulse;     // sampled contacts
    std::vector<double> tangential;  // their tangential rows (sampled_rows_), with friction
    bool frame = false;
  };
  // the sampled rows' P_t of `sample` into kept.tangential
  void keep_tangential(const numerics::ImpactSample& sample, Sample& kept) const;
  // every row's P_t at a sample (zero outside the sampled rows)
  Eigen::VectorXd tangential_impulse(const Sample& sample) const;
  // the velocities of `coordinates` at a sample: v- + M^-1 W P over the sampled contacts
  std::vector<double> velocities(const ImpactOutcome& impact, const Sample& sample,
                                 const std::vector<Eigen::Index>& coordinates) const;

  const ContactModel& model_;
  RecordSpec record_;
  int frame_every_;
  std::vector<Eigen::Index> sampled_;
  std::vector<Eigen::Index> sampled_rows_;  // the sampled contacts' tangential rows, in order
  std::vector<Eigen::Index> recorded_coordinates_;
  std::vector<Sample> samples_;
  std::size_t impacts_seen_ = 0;
  RecordingBudget budget_;
};

}  // namespace mimpact::granular
