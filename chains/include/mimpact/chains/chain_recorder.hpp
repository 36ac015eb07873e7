#pragma once

#include <string>
#include <vector>

#include "mimpact/chains/chain_impact.hpp"
#include "mimpact/chains/chain_scene.hpp"

namespace mimpact::chains {

// Time series of a chain's impacts, against the time since the first impact (s): the force
// of the recorded contacts (N) and the velocity of the recorded bodies (m/s).
struct ChainTimeSeries {
  std::vector<int> contacts, bodies;
  std::vector<double> time;
  std::vector<std::vector<double>> force;     // [sample][recorded contact]
  std::vector<std::vector<double>> velocity;  // [sample][recorded body]

  // "time,F_3,F_9" then one row per sample; "time,v_0,v_20" likewise (17 significant digits)
  std::string forces_csv() const;
  std::string velocities_csv() const;
};

struct CompliantChainRun {
  ChainImpact impact;
  ChainTimeSeries series;
  // the most bodies integrated at once: the others flew in closed form
  Eigen::Index most_bodies_in_motion = 0;
};

// Samples the impulse steps of a chain's impacts (pass it as the impact observer, with the
// sampling it asks for) and gives the time series of RecordSpec once the run is over.
class ChainRecorder : public numerics::ImpactObserver {
 public:
  ChainRecorder(const ChainModel& model, RecordSpec record);

  // The sampling it needs: every record.every impulse steps or record.interval seconds of
  // the adaptive integration, these interactions (the recorded
  // contacts and the ones next to recorded bodies, whose impulses give the bodies' velocities).
  void configure(plugins::LzbImpactOptions& options) const;
  void observe(const numerics::ImpactSample& sample) override;
  ChainTimeSeries series(const ChainImpact& impact) const;

 private:
  struct Sample {
    std::size_t impact;
    double time;                  // s since that impact began
    std::vector<double> force;    // recorded contacts
    std::vector<double> impulse;  // sampled contacts
  };
  const ChainModel& model_;
  RecordSpec record_;
  std::vector<Eigen::Index> sampled_;
  std::vector<Sample> samples_;
  std::size_t impacts_seen_ = 0;
};

}  // namespace mimpact::chains
