#include "mimpact/chains/chain_recorder.hpp"

#include <algorithm>
#include <cstdio>

namespace mimpact::chains {

namespace {

std::string csv(const std::vector<double>& time, const std::vector<std::vector<double>>& rows,
                const std::string& prefix, const std::vector<int>& labels) {
  std::string text = "time";
  for (int label : labels) text += "," + prefix + std::to_string(label);
  text += "\n";
  char number[32];
  for (std::size_t r = 0; r < time.size(); ++r) {
    std::snprintf(number, sizeof number, "%.17g", time[r]);
    text += number;
    for (double value : rows[r]) {
      std::snprintf(number, sizeof number, ",%.17g", value);
      text += number;
    }
    text += "\n";
  }
  return text;
}

}  // namespace

std::string ChainTimeSeries::forces_csv() const { return csv(time, force, "F_", contacts); }
std::string ChainTimeSeries::velocities_csv() const { return csv(time, velocity, "v_", bodies); }

ChainRecorder::ChainRecorder(const ChainModel& model, RecordSpec record)
    : model_(model), record_(std::move(record)) {
  std::vector<Eigen::Index> needed(record_.contacts.begin(), record_.contacts.end());
  // the contacts touching a body are the nonzeros of its row of W
  for (Eigen::Index c = 0; c < model_.W.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(model_.W, c); it; ++it)
      if (std::find(record_.bodies.begin(), record_.bodies.end(), int(it.row())) !=
          record_.bodies.end())
        needed.push_back(c);
  std::sort(needed.begin(), needed.end());
  needed.erase(std::unique(needed.begin(), needed.end()), needed.end());
  sampled_ = needed;
}

void ChainRecorder::configure(plugins::LzbImpactOptions& options) const {
  options.impulse_steps.sample_every = record_.every;
  options.impulse_steps.sampled_contacts = sampled_;
  options.adaptive.sample_interval = record_.interval;
}

void ChainRecorder::observe(const numerics::ImpactSample& sample) {
  if (sample.step == 0) ++impacts_seen_;
  // the sample names its contacts, in increasing order; one outside this impact carries nothing
  auto value_of = [&](std::span<const double> values, Eigen::Index contact) {
    const auto at = std::lower_bound(sample.contacts.begin(), sample.contacts.end(), contact);
    return at != sample.contacts.end() && *at == contact
               ? values[std::size_t(at - sample.contacts.begin())]
               : 0.0;
  };
  Sample kept{impacts_seen_ - 1, sample.time, {}, {}};
  for (Eigen::Index contact : sampled_) kept.impulse.push_back(value_of(sample.impulse, contact));
  for (int contact : record_.contacts) kept.force.push_back(value_of(sample.force, contact));
  samples_.push_back(std::move(kept));
}

ChainTimeSeries ChainRecorder::series(const ChainImpact& impact) const {
  ChainTimeSeries series;
  series.contacts = record_.contacts;
  series.bodies = record_.bodies;
  for (const Sample& sample : samples_) {
    series.time.push_back(impact.impact_times[sample.impact] - impact.impact_time + sample.time);
    series.force.push_back(sample.force);
    // v = v- + M^-1 W P for each recorded body, from the impulses of its contacts
    std::vector<double> velocity;
    for (int body : record_.bodies) {
      double v = impact.velocities_before[sample.impact](body);
      for (std::size_t k = 0; k < sampled_.size(); ++k)
        v += model_.W.coeff(body, sampled_[k]) * sample.impulse[k] / model_.mass(body);
      velocity.push_back(v);
    }
    series.velocity.push_back(std::move(velocity));
  }
  return series;
}

}  // namespace mimpact::chains
