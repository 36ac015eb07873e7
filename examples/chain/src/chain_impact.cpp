#include "mimpact/chain/chain_impact.hpp"

#include <chrono>
#include <cstdio>

namespace mimpact::chain {

ChainImpact simulate_chain_impact(const ChainModel& model, const numerics::LzbOptions& options,
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
