#include "mimpact/chain/chain_impact.hpp"

#include <chrono>

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

nlohmann::json chain_summary(const ChainModel& model, const ChainImpact& impact,
                             double delta_p) {
  using nlohmann::json;
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
      {"contacts", contacts},
      {"impulse_steps", impact.lzb.steps},
      {"impact_duration", impact.lzb.duration},
      {"kinetic_energy",
       {{"before", kinetic_energy(model, model.velocity)},
        {"after", kinetic_energy(model, after)},
        {"residual_potential", impact.lzb.residual_energy}}},
      {"momentum", {{"before", momentum(model, model.velocity)}, {"after", momentum(model, after)}}},
      {"wall_time", impact.wall_time}};
}

}  // namespace mimpact::chain
