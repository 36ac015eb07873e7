#pragma once

#include <vector>

#include "mimpact/chains/chain_scene.hpp"
#include "mimpact/chains/contact_model.hpp"
#include "mimpact/chains/impact_outcome.hpp"
#include "mimpact/chains/time_series.hpp"

namespace mimpact::chains {

// Samples the LZB steps of a scene's impacts (pass it as the impact observer, with the sampling
// it asks for) and gives the time series of RecordSpec once the run is over, and every
// frame_every-th sample a frame of the whole scene (0: none).
class ImpactRecorder : public numerics::ImpactObserver {
 public:
  ImpactRecorder(const ContactModel& model, RecordSpec record, int frame_every = 0);

  // The sampling it needs: every record.every impulse steps or record.interval seconds of
  // the adaptive integration, these interactions (the recorded contacts and the ones touching
  // recorded bodies, whose impulses give the bodies' velocities; all of them for frames).
  void configure(plugins::LzbImpactOptions& options) const;
  void observe(const numerics::ImpactSample& sample) override;
  TimeSeries series(const ImpactOutcome& impact) const;
  Frames frames(const ImpactOutcome& impact) const;

 private:
  struct Sample {
    std::size_t impact;
    double time;                  // s since that impact began
    std::vector<double> force;    // recorded contacts, or all of them in a frame
    std::vector<double> impulse;  // sampled contacts
    bool frame = false;
  };
  // the velocities of `coordinates` at a sample: v- + M^-1 W P over the sampled contacts
  std::vector<double> velocities(const ImpactOutcome& impact, const Sample& sample,
                                 const std::vector<Eigen::Index>& coordinates) const;

  const ContactModel& model_;
  RecordSpec record_;
  int frame_every_;
  std::vector<Eigen::Index> sampled_;
  std::vector<Eigen::Index> recorded_coordinates_;
  std::vector<Sample> samples_;
  std::size_t impacts_seen_ = 0;
};

}  // namespace mimpact::chains
