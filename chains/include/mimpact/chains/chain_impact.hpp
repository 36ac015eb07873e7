#pragma once

#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "mimpact/chains/chain_model.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace mimpact::chains {

// The outcome of the impacts of a chain: the strikers fly to the chain (if there are gaps),
// the shock crosses the touching beads; with strikers arriving at different times, one
// impact after the other. Per-contact results are summed (impulses, steps) or taken at
// their peak over all impacts, times counted from the first impact.
struct ChainImpact {
  numerics::LzbResult lzb;         // aggregated over the impacts
  Eigen::VectorXd velocity_after;  // per body (m/s), after the last impact
  double impact_time = 0.0;        // s, when the first impact began
  double wall_time = 0.0;          // s spent in the impact computations
  // compliant method, free chain: compliant.end_time came with contacts still closed, so the
  // velocities are those at that time, not the chain's final ones (summary status "end_time")
  bool cut_by_end_time = false;
  // the energy ledger beyond lzb.work and lzb.stored_energy (J): the contacts' potential
  // energy at the start (a precompression's) and the work of the bodies' own forces
  Eigen::VectorXd stored_energy_at_start;
  double work_of_forces = 0.0;
  // per impact, in order: when it began (s) and the body velocities just before it
  std::vector<double> impact_times;
  std::vector<Eigen::VectorXd> velocities_before;
};

// Through the kernel: the chain's system, the event-driven integrator, the LZB impact
// problem; the run ends with the impact of the last striker to arrive. `observer` sees the
// samples of every impact (as `options` says) with the chain's contact indices.
ChainImpact simulate_chain_impact(const ChainModel& model, const plugins::LzbImpactOptions& options,
                                  numerics::ImpactObserver* observer = nullptr);
// The same with the impulse steps of `options`.
ChainImpact simulate_chain_impact(const ChainModel& model, const numerics::LzbOptions& options,
                                  numerics::ImpactObserver* observer = nullptr);

// The same impact on numerics alone (H of the model, no kernel), for comparisons: zero
// gaps only.
ChainImpact simulate_chain_impact_numerics(const ChainModel& model,
                                           const numerics::LzbOptions& options,
                                           numerics::ImpactObserver* observer = nullptr);

// Where the kinetic energy of a chain's impacts went (J):
//   kinetic_before + potential_before + work_of_forces
//     = kinetic_after + dissipated_total + potential_left,
// to round-off for every method: each accounts the contacts' work by the trapezoidal rule over
// its own steps, which the velocities follow exactly (docs/model.md, section 12).
struct EnergyLedger {
  double kinetic_before = 0.0, kinetic_after = 0.0;
  double potential_before = 0.0;  // held by the contacts at the start (a precompression)
  double work_of_forces = 0.0;    // done by the bodies' own forces (the precompression)
  Eigen::VectorXd dissipated;     // per contact: its work + its potential energy before - after
  double dissipated_total = 0.0;
  double potential_left = 0.0;  // held by the contacts at the end (LZB: below its tolerance)
  // the two sides' difference (J), round-off
  double imbalance() const;
};

EnergyLedger energy_ledger(const ChainModel& model, const ChainImpact& impact);

struct ChainTimeSeries;

// The impact computed with the compliant contacts integrated in time (method "compliant"):
// the same outcome fields (impulses, peaks and their times from the first contact; steps
// are the integration's), and the recorded time series, sampled every record.interval.
struct CompliantChainRun;
CompliantChainRun simulate_chain_compliant(const ChainModel& model, const CompliantSpec& spec,
                                           const RecordSpec& record);

// The summary.json of `mimpact chain`: post-impact velocities, per-contact peak force, its
// time and impulse, step count, duration, kinetic energy and momentum before and after, and
// the energy ledger ("energy": the fields of EnergyLedger).
// With recorded time series, also the pulse of each recorded contact (Nguyen & Brogliato 2011, eqs.
// 40-43; in a precompressed chain, of the force beyond the static one) and the wave speed through
// each bead whose two contacts are recorded (eq. 41). Keys keep the order written here
// (ordered_json). delta_p is absent (null) for the compliant method.
nlohmann::ordered_json chain_summary(const ChainModel& model, const ChainImpact& impact,
                                     std::optional<double> delta_p,
                                     const ChainTimeSeries* series = nullptr);

// A few lines for people: sizes, the method (`method`, one line: "delta_p = 1e-06 N s"),
// steps, duration, energy and momentum, post-impact velocities (beyond 42 bodies, the first
// and last seven and the extremes: a long chain's report stays a few lines).
std::string chain_report(const ChainModel& model, const ChainImpact& impact,
                         const std::string& method);

}  // namespace mimpact::chains
