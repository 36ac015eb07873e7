#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "mimpact/chains/chain_model.hpp"
#include "mimpact/granular/energy_ledger.hpp"
#include "mimpact/granular/impact_runs.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace mimpact::chains {

// The chain's impacts through the kernel (simulate_impacts on its system); the run ends with the
// impact of the last striker to arrive.
granular::ImpactOutcome simulate_chain_impact(const ChainModel& model,
                                              const plugins::LzbImpactOptions& options,
                                              numerics::ImpactObserver* observer = nullptr);
// The same with the impulse steps of `options`.
granular::ImpactOutcome simulate_chain_impact(const ChainModel& model,
                                              const numerics::LzbOptions& options,
                                              numerics::ImpactObserver* observer = nullptr);

// The same impact on numerics alone (H of the model, no kernel), for comparisons: zero
// gaps only.
granular::ImpactOutcome simulate_chain_impact_numerics(
    const ChainModel& model, const numerics::LzbOptions& options,
    numerics::ImpactObserver* observer = nullptr);

// The impact computed with the compliant contacts integrated in time (method "compliant"),
// simulate_compliant on the chain's system.
granular::CompliantRun simulate_chain_compliant(const ChainModel& model,
                                                const granular::CompliantSpec& spec,
                                                const granular::RecordSpec& record);

// The summary.json of `mimpact chain`: post-impact velocities, per-contact peak force, its
// time and impulse, step count, duration, kinetic energy and momentum before and after, and
// the energy ledger ("energy": the fields of EnergyLedger).
// With recorded time series, also the pulse of each recorded contact (Nguyen & Brogliato 2011, eqs.
// 40-43; in a precompressed chain, of the force beyond the static one) and the wave speed through
// each bead whose two contacts are recorded (eq. 41). Keys keep the order written here
// (ordered_json). delta_p is absent (null) for the compliant method.
nlohmann::ordered_json chain_summary(const ChainModel& model, const granular::ImpactOutcome& impact,
                                     std::optional<double> delta_p,
                                     const granular::TimeSeries* series = nullptr);

// A few lines for people: sizes, the method (`method`, one line: "delta_p = 1e-06 N s"),
// steps, duration, energy and momentum, post-impact velocities (beyond 42 bodies, the first
// and last seven and the extremes: a long chain's report stays a few lines).
std::string chain_report(const ChainModel& model, const granular::ImpactOutcome& impact,
                         const std::string& method);

}  // namespace mimpact::chains
