#include "mimpact/chains/chain_impact.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "mimpact/analysis/pulse_analysis.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/granular/impact_recorder.hpp"

namespace mimpact::chains {

// Pulses of the recorded contacts and wave speeds through beads with both contacts recorded.
// In a precompressed chain a pulse is the force beyond the static one, as Coste, Falcon &
// Fauve (1997) measure it.
void add_pulses(const ChainModel& model, const granular::TimeSeries& series,
                nlohmann::ordered_json& summary) {
  using json = nlohmann::ordered_json;
  json pulses = json::array();
  std::map<int, double> time_of_peak;
  for (std::size_t k = 0; k < series.contacts.size(); ++k) {
    const double static_force = series.contacts[k] >= model.first_bead ? model.precompression : 0.0;
    std::vector<double> force(series.time.size());
    for (std::size_t r = 0; r < series.time.size(); ++r)
      force[r] = series.force[r][k] - static_force;
    if (std::none_of(force.begin(), force.end(), [](double f) { return f > 0.0; })) continue;
    const analysis::PulseMeasures pulse = analysis::measure_pulse(series.time, force);
    time_of_peak[series.contacts[k]] = pulse.time_of_peak;
    // the distinct pulses of the record, those above 1 % of its largest force
    json train = json::array();
    for (const analysis::Peak& peak : analysis::find_pulses(series.time, force, 0.01 * pulse.peak))
      train.push_back({{"time", peak.time}, {"force", peak.force}});
    pulses.push_back({{"contact", series.contacts[k]},
                      {"position", contact_position(model, series.contacts[k])},
                      {"peak", pulse.peak},
                      {"time_of_peak", pulse.time_of_peak},
                      {"width", pulse.width},
                      {"front_impulse", pulse.front_impulse},
                      {"tail_impulse", pulse.tail_impulse},
                      {"pulse_train", train}});
  }
  summary["pulses"] = pulses;
  json speeds = json::array();
  for (const auto& [contact, time] : time_of_peak) {
    const auto left = time_of_peak.find(contact - 1);
    if (left == time_of_peak.end() || !(time > left->second)) continue;
    const double diameter = 2.0 * model.radius(contact);  // bead `contact` lies between them
    speeds.push_back({{"body", contact},
                      {"position", model.position(contact)},
                      {"speed", analysis::wave_speed(diameter, left->second, time)}});
  }
  summary["wave_speeds"] = speeds;
}

granular::ImpactOutcome simulate_chain_impact(const ChainModel& model,
                                              const numerics::LzbOptions& options,
                                              numerics::ImpactObserver* observer) {
  return simulate_chain_impact(
      model, plugins::LzbImpactOptions{.delta_p = options.delta_p, .impulse_steps = options},
      observer);
}

granular::ImpactOutcome simulate_chain_impact(const ChainModel& model,
                                              const plugins::LzbImpactOptions& options,
                                              numerics::ImpactObserver* observer) {
  return granular::simulate_impacts(model, build_chain_system(model), options, observer);
}

granular::ImpactOutcome simulate_chain_impact_numerics(const ChainModel& model,
                                                       const numerics::LzbOptions& options,
                                                       numerics::ImpactObserver* observer) {
  return granular::simulate_impact_numerics(model, options, observer);
}

granular::CompliantRun simulate_chain_compliant(const ChainModel& model,
                                                const granular::CompliantSpec& spec,
                                                const granular::RecordSpec& record) {
  return granular::simulate_compliant(model, build_chain_system(model), spec, {.record = record});
}
nlohmann::ordered_json chain_summary(const ChainModel& model, const granular::ImpactOutcome& impact,
                                     std::optional<double> delta_p,
                                     const granular::TimeSeries* series) {
  using json = nlohmann::ordered_json;
  json contacts = json::array();
  for (Eigen::Index i = 0; i < model.contact_count(); ++i)
    contacts.push_back({{"index", i},
                        {"max_force", impact.result.max_force(i)},
                        {"time_of_max", impact.result.time_of_max_force(i)},
                        {"impulse", impact.result.impulse(i)}});
  const Eigen::VectorXd& after = impact.velocity_after;
  json summary{
      {"status", impact.cut_by_end_time ? "end_time" : numerics::to_string(impact.result.status)},
      {"delta_p", delta_p ? json(*delta_p) : json(nullptr)},
      {"post_impact_velocities", std::vector<double>(after.data(), after.data() + after.size())},
      {"impulse_steps", impact.result.steps},
      {"impacts", impact.impact_times.size()},
      {"impact_time", impact.impact_time},
      {"impact_duration", impact.result.duration},
      {"kinetic_energy",
       {{"before", granular::kinetic_energy(model, model.velocity)},
        {"after", granular::kinetic_energy(model, after)},
        {"residual_potential", impact.result.residual_energy}}},
      {"momentum",
       {{"before", momentum(model, model.velocity)}, {"after", momentum(model, after)}}},
      {"energy", granular::ledger_json(granular::energy_ledger(model, impact))},
      {"wall_time", impact.wall_time},
      {"contacts", contacts}};
  if (series) add_pulses(model, *series, summary);
  return summary;
}

namespace {

// Up to this many bodies the report lists every post-impact velocity; beyond, the first and
// last few and the extremes (summary.json holds them all).
constexpr Eigen::Index kListedBodies = 42;
constexpr Eigen::Index kEndBodies = 7;

std::string velocity_run(const Eigen::VectorXd& velocity, Eigen::Index from, Eigen::Index to) {
  std::string text;
  char value[32];
  for (Eigen::Index i = from; i < to; ++i) {
    std::snprintf(value, sizeof value, "%s%.5g", (i - from) % 7 == 0 ? "\n  " : " ", velocity(i));
    text += value;
  }
  return text;
}

std::string velocity_lines(const Eigen::VectorXd& velocity) {
  const Eigen::Index n = velocity.size();
  if (n <= kListedBodies)
    return "post-impact velocities (m/s, striker first):" + velocity_run(velocity, 0, n) + "\n";
  Eigen::Index slowest, fastest;
  velocity.minCoeff(&slowest);
  velocity.maxCoeff(&fastest);
  char line[256];
  std::snprintf(line, sizeof line,
                "post-impact velocities (m/s) of %lld bodies, all in summary.json; extremes %.5g "
                "(body %lld) and %.5g (body %lld)\n",
                (long long)n, velocity(slowest), (long long)slowest, velocity(fastest),
                (long long)fastest);
  return line + std::string("first ") + std::to_string(kEndBodies) + ":" +
         velocity_run(velocity, 0, kEndBodies) + "\nlast " + std::to_string(kEndBodies) + ":" +
         velocity_run(velocity, n - kEndBodies, n) + "\n";
}

}  // namespace

std::string chain_report(const ChainModel& model, const granular::ImpactOutcome& impact,
                         const std::string& method) {
  const double energy_before = granular::kinetic_energy(model, model.velocity);
  const double energy_after = granular::kinetic_energy(model, impact.velocity_after);
  char line[256];
  std::string report;
  std::snprintf(line, sizeof line, "%lld bodies, %lld contacts, ", (long long)model.body_count(),
                (long long)model.contact_count());
  report += line + method + "\n";
  std::snprintf(
      line, sizeof line, "%lld steps in %.3g s of computation; the impact lasts %.6g s (%s)\n",
      (long long)impact.result.steps, impact.wall_time, impact.result.duration,
      impact.cut_by_end_time ? "cut by compliant.end_time with contacts still closed"
                             : std::string(numerics::to_string(impact.result.status)).c_str());
  report += line;
  std::snprintf(line, sizeof line,
                "kinetic energy %.6g J -> %.6g J (%+.4f %%); momentum %.9g -> %.9g N s\n",
                energy_before, energy_after, 100.0 * (energy_after / energy_before - 1.0),
                momentum(model, model.velocity), momentum(model, impact.velocity_after));
  report += line;
  return report + velocity_lines(impact.velocity_after);
}

}  // namespace mimpact::chains
