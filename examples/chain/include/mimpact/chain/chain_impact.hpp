#pragma once

#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <string>

#include "mimpact/chain/chain_model.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace mimpact::chain {

// The outcome of the multiple impact of a chain: the striker flies to the first bead (if
// there is a gap), then the shock crosses the touching beads in one impact.
struct ChainImpact {
  numerics::LzbResult lzb;
  Eigen::VectorXd velocity_after;  // v+ = v- + M^-1 W P, per body (m/s)
  double impact_time = 0.0;        // s, when the striker touched the first bead
  double wall_time = 0.0;          // s spent in the impact computation
};

// Through the kernel: the chain's system, the event-driven integrator, the LZB impact
// problem; the run ends with the first impact.
ChainImpact simulate_chain_impact(const ChainModel& model, const numerics::LzbOptions& options,
                                  numerics::ImpactObserver* observer = nullptr);

// The same impact on numerics alone (H of the model, no kernel), for comparisons: zero
// gaps only.
ChainImpact simulate_chain_impact_numerics(const ChainModel& model,
                                           const numerics::LzbOptions& options,
                                           numerics::ImpactObserver* observer = nullptr);

// The summary.json of `mimpact chain`: post-impact velocities, per-contact peak force, its
// time and impulse, step count, duration, kinetic energy and momentum before and after.
// Keys keep the order written here (ordered_json).
nlohmann::ordered_json chain_summary(const ChainModel& model, const ChainImpact& impact,
                                     double delta_p);

// A few lines for people: sizes, steps, duration, energy and momentum, post-impact velocities.
std::string chain_report(const ChainModel& model, const ChainImpact& impact, double delta_p);

}  // namespace mimpact::chain
