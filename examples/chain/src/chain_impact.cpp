#include "mimpact/chain/chain_impact.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <optional>

#include "mimpact/chain/chain_recorder.hpp"
#include "mimpact/kernel/simulation.hpp"
#include "mimpact/numerics/error.hpp"
#include "mimpact/numerics/pulse_analysis.hpp"
#include "mimpact/plugins/acceleration_lcp_problem.hpp"
#include "mimpact/plugins/compliant_integrator.hpp"
#include "mimpact/plugins/event_driven_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"

namespace mimpact::chain {

namespace {

// Keeps every impact of the run and ends it with the impact of the last striker to arrive.
class Impacts : public kernel::SimulationObserver {
 public:
  Impacts(const ChainModel& model, const plugins::LzbImpactProblem& lzb, double last_arrival)
      : model_(model), lzb_(lzb), last_arrival_(last_arrival) {
    const Eigen::Index m = model.contact_count();
    total_.impulse = Eigen::VectorXd::Zero(m);
    total_.max_force = Eigen::VectorXd::Zero(m);
    total_.time_of_max_force = Eigen::VectorXd::Zero(m);
  }

  void on_impact(const kernel::Simulation& simulation, const kernel::ImpactReport& report) override {
    // A step the LZB thresholds cannot resolve the approach with would let the striker through.
    if (lzb_.last_result().steps == 0)
      throw InvalidInput("the impact at t = " + to_text(report.time) +
                         " s took no impulse step: no contact approaches faster than the LZB velocity "
                         "threshold (0.1 H_jj delta_p, or impact.fixed_thresholds.velocity); take a "
                         "smaller delta_p or threshold");
    const kernel::NonSmoothDynamicalSystem& system = simulation.system();
    Eigen::VectorXd velocity(system.system_count());
    for (kernel::Index k = 0; k < system.system_count(); ++k) velocity(k) = system.system(k).velocity()(0);
    if (result_.impact_times.empty()) result_.impact_time = report.time;
    const double offset = report.time - result_.impact_time;
    Eigen::VectorXd impulse = Eigen::VectorXd::Zero(model_.contact_count());
    for (std::size_t k = 0; k < report.interactions.size(); ++k) {
      const kernel::Index j = report.interactions[k];
      impulse(j) = report.impulse(Eigen::Index(k));
      if (report.max_force(Eigen::Index(k)) > total_.max_force(j)) {
        total_.max_force(j) = report.max_force(Eigen::Index(k));
        total_.time_of_max_force(j) = offset + report.time_of_max_force(Eigen::Index(k));
      }
    }
    total_.impulse += impulse;
    total_.steps += lzb_.last_result().steps;
    total_.contact_steps += lzb_.last_result().contact_steps;
    total_.residual_energy += lzb_.last_result().residual_energy;
    total_.duration = offset + report.duration;
    result_.wall_time += report.wall_time;
    result_.impact_times.push_back(report.time);
    result_.velocities_before.push_back(
        velocity - (model_.W * impulse).cwiseQuotient(model_.mass));
    result_.velocity_after = velocity;
    if (report.time >= last_arrival_ - 1e-9) const_cast<kernel::Simulation&>(simulation).stop();
  }

  ChainImpact result() {
    if (result_.impact_times.empty())
      throw Error("the strikers never reached the chain within the simulated time");
    total_.velocity = model_.W.transpose() * result_.velocity_after;
    result_.lzb = total_;
    return result_;
  }

 private:
  const ChainModel& model_;
  const plugins::LzbImpactProblem& lzb_;
  double last_arrival_;
  numerics::LzbResult total_;
  ChainImpact result_;
};

}  // namespace

// Pulses of the recorded contacts and wave speeds through beads with both contacts recorded.
// In a precompressed chain a pulse is the force beyond the static one, as seed 001 measures it.
void add_pulses(const ChainModel& model, const ChainTimeSeries& series,
                nlohmann::ordered_json& summary) {
  using json = nlohmann::ordered_json;
  json pulses = json::array();
  std::map<int, double> time_of_peak;
  for (std::size_t k = 0; k < series.contacts.size(); ++k) {
    const double static_force = series.contacts[k] >= model.first_bead ? model.precompression : 0.0;
    std::vector<double> force(series.time.size());
    for (std::size_t r = 0; r < series.time.size(); ++r) force[r] = series.force[r][k] - static_force;
    if (std::none_of(force.begin(), force.end(), [](double f) { return f > 0.0; })) continue;
    const numerics::PulseMeasures pulse = numerics::measure_pulse(series.time, force);
    time_of_peak[series.contacts[k]] = pulse.time_of_peak;
    // the distinct pulses of the record, those above 1 % of its largest force
    json train = json::array();
    for (const numerics::Peak& peak : numerics::find_pulses(series.time, force, 0.01 * pulse.peak))
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
                      {"speed", numerics::wave_speed(diameter, left->second, time)}});
  }
  summary["wave_speeds"] = speeds;
}

ChainImpact simulate_chain_impact(const ChainModel& model, const numerics::LzbOptions& options,
                                  numerics::ImpactObserver* observer) {
  plugins::LzbImpactOptions impact_options;
  impact_options.integrator = options;
  auto impacts = std::make_unique<plugins::LzbImpactProblem>(impact_options);
  plugins::LzbImpactProblem& lzb = *impacts;
  lzb.set_observer(observer);
  kernel::Simulation simulation(build_chain_system(model),
                                std::make_unique<plugins::EventDrivenIntegrator>(),
                                std::move(impacts),
                                std::make_unique<plugins::AccelerationLcpProblem>());
  const double last_arrival =
      *std::max_element(model.striker_arrivals.begin(), model.striker_arrivals.end());
  Impacts all(model, lzb, last_arrival);
  simulation.add_observer(all);
  simulation.run(0.0, 2.0 * last_arrival + 1.0);
  return all.result();
}

CompliantChainRun simulate_chain_compliant(const ChainModel& model, const CompliantSpec& spec,
                                           const RecordSpec& record) {
  plugins::CompliantOptions options;
  options.relative_tolerance = spec.tolerance;
  options.absolute_tolerance = 1e-4 * spec.tolerance;
  auto owned = std::make_unique<plugins::CompliantIntegrator>(options);
  plugins::CompliantIntegrator& integrator = *owned;
  auto system = build_chain_system(model);
  kernel::SimulationOptions simulation_options;
  simulation_options.penetration_tolerance += model.largest_static_overlap;  // precompressed
  kernel::Simulation simulation(system, std::move(owned), std::make_unique<plugins::LzbImpactProblem>(),
                                std::make_unique<plugins::AccelerationLcpProblem>(), simulation_options);
  const double end = spec.end_time.value_or(1.0);
  const bool recording = !record.contacts.empty() || !record.bodies.empty();
  if (recording) simulation.schedule_outputs(0.0, record.interval, end);

  // samples the recorded contacts and bodies; ends a free chain once it has come apart
  struct Watch : kernel::SimulationObserver {
    const plugins::CompliantIntegrator* integrator;
    const RecordSpec* record;
    bool precompressed;
    ChainTimeSeries series;
    double first_contact = -1.0;
    void on_output(const kernel::Simulation& s) override {
      series.time.push_back(s.time());
      std::vector<double> forces, velocities;
      for (int c : record->contacts) forces.push_back(integrator->forces()[std::size_t(c)]);
      for (int b : record->bodies) velocities.push_back(s.system().system(b).velocity()(0));
      series.force.push_back(forces);
      series.velocity.push_back(velocities);
    }
    void on_step(const kernel::Simulation& s, const kernel::StepReport& step) override {
      if (!step.closing.empty() && first_contact < 0.0) first_contact = step.time;
      if (!step.detaching.empty()) last_opening = step.time;
      if (!precompressed && first_contact >= 0.0 && integrator->contacts_open())
        const_cast<kernel::Simulation&>(s).stop();
    }
    double last_opening = -1.0;
  } watch;
  watch.integrator = &integrator;
  watch.record = &record;
  watch.precompressed = model.precompression > 0.0;
  // a striker with no gap touches at t = 0: the impact starts at once, with no closing event
  if (std::find(model.striker_arrivals.begin(), model.striker_arrivals.end(), 0.0) != model.striker_arrivals.end())
    watch.first_contact = 0.0;
  watch.series.contacts = record.contacts;
  watch.series.bodies = record.bodies;
  simulation.add_observer(watch);
  const auto clock = std::chrono::steady_clock::now();
  const kernel::RunSummary summary = simulation.run(0.0, end);

  CompliantChainRun run;
  ChainImpact& impact = run.impact;
  impact.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
  // touching strikers start in contact: no closing event, the impact begins at 0
  impact.impact_time = std::max(0.0, watch.first_contact);
  const Eigen::Index m = model.contact_count();
  impact.lzb.impulse = Eigen::Map<const Eigen::VectorXd>(integrator.impulses().data(), m);
  impact.lzb.max_force = Eigen::Map<const Eigen::VectorXd>(integrator.max_forces().data(), m);
  impact.lzb.time_of_max_force =
      Eigen::Map<const Eigen::VectorXd>(integrator.times_of_max_force().data(), m).array() - impact.impact_time;
  impact.lzb.steps = summary.smooth_steps;
  impact.cut_by_end_time = !watch.precompressed && !integrator.contacts_open();
  // a free chain's impact lasts until its last contact opens; a precompressed one's, the run
  impact.lzb.duration =
      (watch.precompressed || watch.last_opening < 0.0 ? summary.end_time : watch.last_opening) - impact.impact_time;
  impact.velocity_after.resize(model.body_count());
  for (Eigen::Index k = 0; k < model.body_count(); ++k) impact.velocity_after(k) = system->system(k).velocity()(0);
  impact.lzb.velocity = model.W.transpose() * impact.velocity_after;
  impact.impact_times = {impact.impact_time};
  impact.velocities_before = {model.velocity};
  run.series = std::move(watch.series);
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
  impact.velocity_after =
      model.velocity + (model.W * impact.lzb.impulse).cwiseQuotient(model.mass);
  impact.impact_times = {0.0};
  impact.velocities_before = {model.velocity};
  return impact;
}

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
      {"momentum", {{"before", momentum(model, model.velocity)}, {"after", momentum(model, after)}}},
      {"wall_time", impact.wall_time},
      {"contacts", contacts}};
  if (series) add_pulses(model, *series, summary);
  return summary;
}

std::string chain_report(const ChainModel& model, const ChainImpact& impact, std::optional<double> delta_p) {
  const double energy_before = kinetic_energy(model, model.velocity);
  const double energy_after = kinetic_energy(model, impact.velocity_after);
  char line[256];
  std::string report;
  std::snprintf(line, sizeof line, "%lld bodies, %lld contacts, ", (long long)model.body_count(),
                (long long)model.contact_count());
  report += line;
  if (delta_p)
    std::snprintf(line, sizeof line, "delta_p = %g N s\n", *delta_p);
  else
    std::snprintf(line, sizeof line, "compliant contacts integrated in time\n");
  report += line;
  std::snprintf(line, sizeof line,
                "%lld impulse steps in %.3g s of computation; the impact lasts %.6g s (%s)\n",
                (long long)impact.lzb.steps, impact.wall_time, impact.lzb.duration,
                impact.cut_by_end_time ? "cut by compliant.end_time with contacts still closed"
                                       : std::string(numerics::to_string(impact.lzb.status)).c_str());
  report += line;
  std::snprintf(line, sizeof line,
                "kinetic energy %.6g J -> %.6g J (%+.4f %%); momentum %.9g -> %.9g N s\n",
                energy_before, energy_after, 100.0 * (energy_after / energy_before - 1.0),
                momentum(model, model.velocity), momentum(model, impact.velocity_after));
  report += line;
  report += "post-impact velocities (m/s, striker first):";
  for (Eigen::Index i = 0; i < impact.velocity_after.size(); ++i) {
    std::snprintf(line, sizeof line, "%s%.5g", i % 7 == 0 ? "\n  " : " ",
                  impact.velocity_after(i));
    report += line;
  }
  return report + "\n";
}

}  // namespace mimpact::chain
