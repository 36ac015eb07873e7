#include "mimpact/chain/chain_impact.hpp"

#include <chrono>
#include <optional>

#include "mimpact/kernel/simulation.hpp"
#include "mimpact/numerics/error.hpp"
#include "mimpact/plugins/acceleration_lcp_problem.hpp"
#include "mimpact/plugins/event_driven_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"
#include <cstdio>

namespace mimpact::chain {

namespace {

// Ends the run at the first impact and keeps what it did.
class FirstImpact : public kernel::SimulationObserver {
 public:
  void on_impact(const kernel::Simulation& simulation, const kernel::ImpactReport& report) override {
    impact = report;
    const kernel::NonSmoothDynamicalSystem& system = simulation.system();
    velocity_after.resize(system.system_count());
    for (kernel::Index k = 0; k < system.system_count(); ++k)
      velocity_after(k) = system.system(k).velocity()(0);
    const_cast<kernel::Simulation&>(simulation).stop();
  }
  std::optional<kernel::ImpactReport> impact;
  Eigen::VectorXd velocity_after;
};

}  // namespace

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
  FirstImpact first;
  simulation.add_observer(first);
  // the striker reaches the first bead at gap / V; give it twice that
  const double gap = model.position(1) - model.position(0) - model.radius(0) - model.radius(1);
  simulation.run(0.0, 2.0 * gap / model.velocity(0) + 1.0);
  if (!first.impact)
    throw Error("the striker never reached the chain");  // a validated scene cannot get here
  ChainImpact impact;
  impact.lzb = lzb.last_result();
  impact.velocity_after = first.velocity_after;
  impact.impact_time = first.impact->time;
  impact.wall_time = first.impact->wall_time;
  return impact;
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
  return impact;
}

nlohmann::ordered_json chain_summary(const ChainModel& model, const ChainImpact& impact,
                                     double delta_p) {
  using json = nlohmann::ordered_json;
  json contacts = json::array();
  for (Eigen::Index i = 0; i < model.contact_count(); ++i)
    contacts.push_back({{"index", i},
                        {"max_force", impact.lzb.max_force(i)},
                        {"time_of_max", impact.lzb.time_of_max_force(i)},
                        {"impulse", impact.lzb.impulse(i)}});
  const Eigen::VectorXd& after = impact.velocity_after;
  return json{
      {"status", numerics::to_string(impact.lzb.status)},
      {"delta_p", delta_p},
      {"post_impact_velocities", std::vector<double>(after.data(), after.data() + after.size())},
      {"impulse_steps", impact.lzb.steps},
      {"impact_time", impact.impact_time},
      {"impact_duration", impact.lzb.duration},
      {"kinetic_energy",
       {{"before", kinetic_energy(model, model.velocity)},
        {"after", kinetic_energy(model, after)},
        {"residual_potential", impact.lzb.residual_energy}}},
      {"momentum", {{"before", momentum(model, model.velocity)}, {"after", momentum(model, after)}}},
      {"wall_time", impact.wall_time},
      {"contacts", contacts}};
}

std::string chain_report(const ChainModel& model, const ChainImpact& impact, double delta_p) {
  const double energy_before = kinetic_energy(model, model.velocity);
  const double energy_after = kinetic_energy(model, impact.velocity_after);
  char line[256];
  std::string report;
  std::snprintf(line, sizeof line, "%lld bodies, %lld contacts, delta_p = %g N s\n",
                (long long)model.body_count(), (long long)model.contact_count(), delta_p);
  report += line;
  std::snprintf(line, sizeof line,
                "%lld impulse steps in %.3g s of computation; the impact lasts %.6g s (%s)\n",
                (long long)impact.lzb.steps, impact.wall_time, impact.lzb.duration,
                std::string(numerics::to_string(impact.lzb.status)).c_str());
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
