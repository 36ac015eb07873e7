#include "mimpact/numerics/impact_observer.hpp"

namespace mimpact::numerics {

void ImpactHistory::observe(const ImpactSample& sample) {
  if (step.empty()) contacts.assign(sample.contacts.begin(), sample.contacts.end());
  step.push_back(sample.step);
  time.push_back(sample.time);
  principal_impulse.push_back(sample.principal_impulse);
  velocity.emplace_back(sample.velocity.begin(), sample.velocity.end());
  energy.emplace_back(sample.energy.begin(), sample.energy.end());
  force.emplace_back(sample.force.begin(), sample.force.end());
  impulse.emplace_back(sample.impulse.begin(), sample.impulse.end());
}

}  // namespace mimpact::numerics
