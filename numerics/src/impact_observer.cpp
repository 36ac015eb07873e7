#include "mimpact/numerics/impact_observer.hpp"

#include <limits>

namespace mimpact::numerics {

ObserverSchedule::ObserverSchedule(const ImpactObserver* observer, std::int64_t sample_every)
    : sample_every_(sample_every > 0 ? sample_every : 0),
      next_(observer ? next_of(0) : std::numeric_limits<std::int64_t>::max()) {}

// The first step after `step` that is a progress report's or a sample's: the nearer of the two,
// each found as its gap from `step`, so that a sampling period near the largest count of steps
// does not overflow.
std::int64_t ObserverSchedule::next_of(std::int64_t step) const {
  const std::int64_t progress =
      step + (ImpactObserver::kProgressSteps - step % ImpactObserver::kProgressSteps);
  if (sample_every_ == 0) return progress;
  const std::int64_t left = sample_every_ - step % sample_every_;
  return left >= progress - step ? progress : step + left;
}

ObserverSchedule::Due ObserverSchedule::take(std::int64_t step) {
  const Due due{.sample = sample_every_ > 0 && step % sample_every_ == 0,
                .progress = step % ImpactObserver::kProgressSteps == 0};
  next_ = next_of(step);
  return due;
}

void ImpactSampler::reset(std::span<const Eigen::Index> contacts, std::size_t contact_count,
                          const TangentialRows* rows) {
  contacts_.assign(contacts.begin(), contacts.end());
  if (contacts_.empty())
    for (std::size_t j = 0; j < contact_count; ++j) contacts_.push_back(Eigen::Index(j));
  velocity_.assign(contacts_.size(), 0.0);
  energy_.assign(contacts_.size(), 0.0);
  force_.assign(contacts_.size(), 0.0);
  impulse_.assign(contacts_.size(), 0.0);
  tangential_rows_.clear();
  if (rows)
    for (Eigen::Index j : contacts_)
      for (Eigen::Index r = rows->first_row[std::size_t(j)];
           r < rows->first_row[std::size_t(j) + 1]; ++r)
        tangential_rows_.push_back(r);
  tangential_.assign(tangential_rows_.size(), 0.0);
}

void ImpactSampler::send(ImpactObserver& observer, std::int64_t step, double time,
                         double principal_impulse) {
  ImpactSample sample;
  sample.step = step;
  sample.time = time;
  sample.principal_impulse = principal_impulse;
  sample.contacts = contacts_;
  sample.velocity = velocity_;
  sample.energy = energy_;
  sample.force = force_;
  sample.impulse = impulse_;
  sample.tangential_impulse = tangential_;
  observer.observe(sample);
}

void ImpactHistory::observe(const ImpactSample& sample) {
  if (step.empty()) contacts.assign(sample.contacts.begin(), sample.contacts.end());
  step.push_back(sample.step);
  time.push_back(sample.time);
  principal_impulse.push_back(sample.principal_impulse);
  velocity.emplace_back(sample.velocity.begin(), sample.velocity.end());
  energy.emplace_back(sample.energy.begin(), sample.energy.end());
  force.emplace_back(sample.force.begin(), sample.force.end());
  impulse.emplace_back(sample.impulse.begin(), sample.impulse.end());
  tangential_impulse.emplace_back(sample.tangential_impulse.begin(),
                                  sample.tangential_impulse.end());
}

}  // namespace mimpact::numerics
