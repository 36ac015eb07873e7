#include "mimpact/chains/chain_impact.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>

#include "mimpact/analysis/pulse_analysis.hpp"
#include "mimpact/chains/chain_recorder.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/kernel/registry.hpp"
#include "mimpact/kernel/simulation.hpp"
#include "mimpact/plugins/compliant_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"
#include "mimpact/plugins/register_plugins.hpp"

namespace mimpact::chains {

namespace {

// Keeps every impact of the run and ends it with the impact of the last striker to arrive.
class Impacts : public kernel::SimulationObserver {
 public:
  Impacts(const ChainModel& model, double last_arrival)
      : model_(model), last_arrival_(last_arrival) {
    const Eigen::Index m = model.contact_count();
    total_.impulse = Eigen::VectorXd::Zero(m);
    total_.max_force = Eigen::VectorXd::Zero(m);
    total_.time_of_max_force = Eigen::VectorXd::Zero(m);
    total_.work = Eigen::VectorXd::Zero(m);
    total_.stored_energy = Eigen::VectorXd::Zero(m);
  }

  kernel::EventStatus on_step(const kernel::Simulation&, const kernel::StepReport& step) override {
    if (!step.impact) return kernel::EventStatus::proceed();
    add(*step.impact);
    return step.impact->time >= last_arrival_ - 1e-9
               ? kernel::EventStatus::terminate("the last striker has struck")
               : kernel::EventStatus::proceed();
  }

  ChainImpact result() {
    if (result_.impact_times.empty())
      throw Error("the strikers never reached the chain within the simulated time");
    total_.velocity = model_.W.transpose() * result_.velocity_after;
    result_.lzb = total_;
    return result_;
  }

 private:
  void add(const kernel::ImpactReport& report) {
    // A step the LZB thresholds cannot resolve the approach with would let the striker through.
    if (report.steps == 0)
      throw InvalidInput(
          "the impact at t = " + to_text(report.time) +
          " s took no impulse step: no contact approaches faster than the LZB velocity "
          "threshold (0.1 H_jj delta_p, or impact.fixed_thresholds.velocity); take a "
          "smaller delta_p or threshold");
    if (result_.impact_times.empty()) result_.impact_time = report.time;
    const double offset = report.time - result_.impact_time;
    for (std::size_t k = 0; k < report.interactions.size(); ++k) {
      const kernel::Index j = report.interactions[k];
      total_.impulse(j) += report.impulse(Eigen::Index(k));
      total_.work(j) += report.work(Eigen::Index(k));
      total_.stored_energy(j) += report.stored_energy(Eigen::Index(k));
      if (report.max_force(Eigen::Index(k)) > total_.max_force(j)) {
        total_.max_force(j) = report.max_force(Eigen::Index(k));
        total_.time_of_max_force(j) = offset + report.time_of_max_force(Eigen::Index(k));
      }
    }
    total_.steps += report.steps;
    total_.contact_steps += report.contact_steps;
    total_.residual_energy += report.residual_energy;
    total_.duration = offset + report.duration;
    result_.wall_time += report.wall_time;
    result_.impact_times.push_back(report.time);
    result_.velocities_before.push_back(report.generalized_velocity_before);
    result_.velocity_after = report.generalized_velocity_after;
  }

  const ChainModel& model_;
  double last_arrival_;
  numerics::LzbResult total_;
  ChainImpact result_;
};

// Samples the recorded contacts and bodies of a compliant run; ends a free chain once it has
// come apart.
class CompliantWatch : public kernel::SimulationObserver {
 public:
  CompliantWatch(const RecordSpec& record, bool precompressed, bool touching_at_start)
      : record_(record), precompressed_(precompressed) {
    // a striker with no gap touches at t = 0: the impact starts at once, with no closing event
    if (touching_at_start) first_contact_ = 0.0;
    series_.contacts = record.contacts;
    series_.bodies = record.bodies;
  }

  void on_output(const kernel::Simulation& s) override {
    const kernel::ContactForceHistory& history = *s.integrator().contact_force_history();
    series_.time.push_back(s.time());
    std::vector<double> forces, velocities;
    for (int c : record_.contacts) forces.push_back(history.force(c));
    for (int b : record_.bodies) velocities.push_back(s.system().system(b).velocity()(0));
    series_.force.push_back(forces);
    series_.velocity.push_back(velocities);
  }

  kernel::EventStatus on_step(const kernel::Simulation& s,
                              const kernel::StepReport& step) override {
    if (!step.closing.empty() && first_contact_ < 0.0) first_contact_ = step.time;
    if (!step.detaching.empty()) last_opening_ = step.time;
    if (!precompressed_ && first_contact_ >= 0.0 &&
        s.integrator().contact_force_history()->all_open)
      return kernel::EventStatus::terminate("the chain has come apart");
    return kernel::EventStatus::proceed();
  }

  double first_contact() const { return first_contact_; }
  double last_opening() const { return last_opening_; }
  ChainTimeSeries take_series() { return std::move(series_); }

 private:
  const RecordSpec& record_;
  bool precompressed_;
  ChainTimeSeries series_;
  double first_contact_ = -1.0, last_opening_ = -1.0;
};

}  // namespace

// Pulses of the recorded contacts and wave speeds through beads with both contacts recorded.
// In a precompressed chain a pulse is the force beyond the static one, as Coste, Falcon &
// Fauve (1997) measure it.
void add_pulses(const ChainModel& model, const ChainTimeSeries& series,
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

ChainImpact simulate_chain_impact(const ChainModel& model, const numerics::LzbOptions& options,
                                  numerics::ImpactObserver* observer) {
  return simulate_chain_impact(model, plugins::LzbImpactOptions{.impulse_steps = options},
                               observer);
}

ChainImpact simulate_chain_impact(const ChainModel& model, const plugins::LzbImpactOptions& options,
                                  numerics::ImpactObserver* observer) {
  plugins::register_plugins();
  auto impacts = kernel::impact_problems().create("lzb", kernel::to_parameters(options));
  impacts->set_impact_observer(observer);
  kernel::Simulation simulation(
      build_chain_system(model), kernel::integrators().create("event-driven"),
      {.impacts = std::move(impacts),
       .contact_forces = kernel::contact_force_problems().create("acceleration-lcp")});
  const double last_arrival =
      *std::max_element(model.striker_arrivals.begin(), model.striker_arrivals.end());
  Impacts all(model, last_arrival);
  simulation.add_observer(all);
  simulation.run(0.0, 2.0 * last_arrival + 1.0);
  return all.result();
}

namespace {

// Overlaps below this share of the impact's are never integrated (CompliantOptions): their
// force is below 1e-9 of the peak force.
constexpr double kOverlapResolution = 1e-6;
constexpr double kLoosestTolerance = 1e-4;

// The impact's overlap, or the static one of a precompressed chain struck by nothing.
double overlap_scale(const ChainModel& model) {
  const double overlap = impact_overlap(model);
  return std::isfinite(overlap) ? overlap : std::max(model.largest_static_overlap, 1e-6);
}

}  // namespace

CompliantChainRun simulate_chain_compliant(const ChainModel& model, const CompliantSpec& spec,
                                           const RecordSpec& record) {
  plugins::register_plugins();
  auto system = build_chain_system(model);
  // Looser than kLoosestTolerance, the integration's velocity errors set off collisions in the
  // wake of the wave that cost more steps than the looser control saves.
  const double tolerance = std::min(spec.tolerance, kLoosestTolerance);
  // A contact approaching at tolerance x V holds tolerance^(2 / (1 + eta)) of the impact's
  // overlap: overlaps up to ten times that are the integration's own error (its velocities
  // carry tolerance x V), not worth integrating.
  const double overlap = overlap_scale(model);
  const double resolution =
      std::max(kOverlapResolution,
               10.0 * std::pow(tolerance, 2.0 / (1.0 + model.laws.front().exponent))) *
      overlap;
  kernel::SimulationOptions simulation_options;
  simulation_options.penetration_tolerance += model.largest_static_overlap;  // precompressed
  kernel::Simulation simulation(
      system,
      kernel::integrators().create(
          "compliant", {{"relative_tolerance", tolerance},
                        // the positions to the tolerance's share of the impact's overlap
                        {"absolute_tolerance", 1e-2 * tolerance * overlap},
                        {"overlap_resolution", resolution}}),
      {}, simulation_options);
  const double end = spec.end_time.value_or(1.0);
  const bool recording = !record.contacts.empty() || !record.bodies.empty();
  if (recording) simulation.schedule_outputs(0.0, record.interval, end);
  const bool precompressed = model.precompression > 0.0;
  CompliantWatch watch(record, precompressed,
                       std::find(model.striker_arrivals.begin(), model.striker_arrivals.end(),
                                 0.0) != model.striker_arrivals.end());
  simulation.add_observer(watch);
  const auto clock = std::chrono::steady_clock::now();
  const kernel::RunSummary summary = simulation.run(0.0, end);
  const kernel::ContactForceHistory& history = *simulation.integrator().contact_force_history();

  CompliantChainRun run;
  ChainImpact& impact = run.impact;
  impact.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
  // touching strikers start in contact: no closing event, the impact begins at 0
  impact.impact_time = std::max(0.0, watch.first_contact());
  impact.lzb.impulse = history.impulse;
  impact.lzb.max_force = history.max_force;
  impact.lzb.time_of_max_force = history.time_of_max_force.array() - impact.impact_time;
  impact.lzb.steps = summary.smooth_steps;
  impact.lzb.work = history.work;
  impact.lzb.stored_energy = history.stored_energy;
  impact.stored_energy_at_start = history.stored_energy_at_start;
  impact.work_of_forces = history.work_of_forces;
  impact.cut_by_end_time = !precompressed && !history.all_open;
  // a free chain's impact lasts until its last contact opens; a precompressed one's, the run
  impact.lzb.duration =
      (precompressed || watch.last_opening() < 0.0 ? summary.end_time : watch.last_opening()) -
      impact.impact_time;
  impact.velocity_after.resize(model.body_count());
  for (Eigen::Index k = 0; k < model.body_count(); ++k)
    impact.velocity_after(k) = system->system(k).velocity()(0);
  impact.lzb.velocity = model.W.transpose() * impact.velocity_after;
  impact.impact_times = {impact.impact_time};
  impact.velocities_before = {model.velocity};
  run.series = watch.take_series();
  run.most_bodies_in_motion =
      dynamic_cast<const plugins::CompliantIntegrator&>(simulation.integrator())
          .most_bodies_in_motion();
  for (double& t : run.series.time) t -= impact.impact_time;
  return run;
}

ChainImpact simulate_chain_impact_numerics(const ChainModel& model,
                                           const numerics::LzbOptions& options,
                                           numerics::ImpactObserver* observer) {
  numerics::LzbImpulseIntegrator integrator(options);
  ChainImpact impact;
  const auto start = std::chrono::steady_clock::now();
  impact.lzb = integrator.integrate(model.H, model.u_minus, model.laws, observer);
  impact.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  impact.velocity_after = model.velocity + (model.W * impact.lzb.impulse).cwiseQuotient(model.mass);
  impact.impact_times = {0.0};
  impact.velocities_before = {model.velocity};
  return impact;
}

double EnergyLedger::imbalance() const {
  return kinetic_before + potential_before + work_of_forces -
         (kinetic_after + dissipated_total + potential_left);
}

EnergyLedger energy_ledger(const ChainModel& model, const ChainImpact& impact) {
  EnergyLedger ledger;
  ledger.kinetic_before = kinetic_energy(model, model.velocity);
  ledger.kinetic_after = kinetic_energy(model, impact.velocity_after);
  const Eigen::Index m = model.contact_count();
  const Eigen::VectorXd& stored_after = impact.lzb.stored_energy;
  const Eigen::VectorXd stored_before = impact.stored_energy_at_start.size() == m
                                            ? impact.stored_energy_at_start
                                            : Eigen::VectorXd::Zero(m);
  if (impact.lzb.work.size() != m || stored_after.size() != m)
    throw Error("the impact's method kept no energy ledger (nonlinear relations)");
  ledger.potential_before = stored_before.sum();
  ledger.work_of_forces = impact.work_of_forces;
  ledger.dissipated = impact.lzb.work + stored_before - stored_after;
  ledger.dissipated_total = ledger.dissipated.sum();
  ledger.potential_left = stored_after.sum();
  return ledger;
}

namespace {

nlohmann::ordered_json ledger_json(const EnergyLedger& ledger) {
  const Eigen::VectorXd& d = ledger.dissipated;
  return {{"kinetic_before", ledger.kinetic_before},
          {"potential_before", ledger.potential_before},
          {"work_of_forces", ledger.work_of_forces},
          {"kinetic_after", ledger.kinetic_after},
          {"dissipated", std::vector<double>(d.data(), d.data() + d.size())},
          {"dissipated_total", ledger.dissipated_total},
          {"potential_left", ledger.potential_left}};
}

}  // namespace

nlohmann::ordered_json chain_summary(const ChainModel& model, const ChainImpact& impact,
                                     std::optional<double> delta_p, const ChainTimeSeries* series) {
  using json = nlohmann::ordered_json;
  json contacts = json::array();
  for (Eigen::Index i = 0; i < model.contact_count(); ++i)
    contacts.push_back({{"index", i},
                        {"max_force", impact.lzb.max_force(i)},
                        {"time_of_max", impact.lzb.time_of_max_force(i)},
                        {"impulse", impact.lzb.impulse(i)}});
  const Eigen::VectorXd& after = impact.velocity_after;
  json summary{
      {"status", impact.cut_by_end_time ? "end_time" : numerics::to_string(impact.lzb.status)},
      {"delta_p", delta_p ? json(*delta_p) : json(nullptr)},
      {"post_impact_velocities", std::vector<double>(after.data(), after.data() + after.size())},
      {"impulse_steps", impact.lzb.steps},
      {"impacts", impact.impact_times.size()},
      {"impact_time", impact.impact_time},
      {"impact_duration", impact.lzb.duration},
      {"kinetic_energy",
       {{"before", kinetic_energy(model, model.velocity)},
        {"after", kinetic_energy(model, after)},
        {"residual_potential", impact.lzb.residual_energy}}},
      {"momentum",
       {{"before", momentum(model, model.velocity)}, {"after", momentum(model, after)}}},
      {"energy", ledger_json(energy_ledger(model, impact))},
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

std::string chain_report(const ChainModel& model, const ChainImpact& impact,
                         const std::string& method) {
  const double energy_before = kinetic_energy(model, model.velocity);
  const double energy_after = kinetic_energy(model, impact.velocity_after);
  char line[256];
  std::string report;
  std::snprintf(line, sizeof line, "%lld bodies, %lld contacts, ", (long long)model.body_count(),
                (long long)model.contact_count());
  report += line + method + "\n";
  std::snprintf(
      line, sizeof line, "%lld steps in %.3g s of computation; the impact lasts %.6g s (%s)\n",
      (long long)impact.lzb.steps, impact.wall_time, impact.lzb.duration,
      impact.cut_by_end_time ? "cut by compliant.end_time with contacts still closed"
                             : std::string(numerics::to_string(impact.lzb.status)).c_str());
  report += line;
  std::snprintf(line, sizeof line,
                "kinetic energy %.6g J -> %.6g J (%+.4f %%); momentum %.9g -> %.9g N s\n",
                energy_before, energy_after, 100.0 * (energy_after / energy_before - 1.0),
                momentum(model, model.velocity), momentum(model, impact.velocity_after));
  report += line;
  return report + velocity_lines(impact.velocity_after);
}

}  // namespace mimpact::chains
