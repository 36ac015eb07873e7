#pragma once

// Running the chain scenes of examples/scenes in the tests.

#include <cmath>
#include <string>

#include "mimpact/chains/chain_impact.hpp"
#include "mimpact/chains/chain_model.hpp"
#include "mimpact/chains/chain_scene.hpp"

namespace mimpact::testing {

inline chains::ChainModel scene_model(const std::string& name) {
  return chains::build_chain_model(
      chains::load_chain_scene(std::string(MIMPACT_SOURCE_DIR) + "/examples/scenes/" + name));
}

inline granular::ImpactOutcome run_chain(const chains::ChainModel& model, double delta_p,
                                         numerics::ImpactObserver* observer = nullptr,
                                         std::int64_t sample_every = 0) {
  numerics::LzbOptions options;
  options.delta_p = delta_p;
  options.sample_every = sample_every;
  return chains::simulate_chain_impact(model, options, observer);
}

// Relative to the momentum the bodies carry, sum m |v|: the total is zero when strikers meet
// from both sides.
// The adaptive LZB integrator at `tolerance`, through the kernel.
inline granular::ImpactOutcome run_adaptive(const chains::ChainModel& model, double tolerance) {
  plugins::LzbImpactOptions options;
  options.integrator = plugins::LzbIntegrator::adaptive;
  options.tolerance = tolerance;
  return chains::simulate_chain_impact(model, options);
}

inline double relative_momentum_change(const chains::ChainModel& model,
                                       const granular::ImpactOutcome& impact) {
  const double before = chains::momentum(model, model.velocity);
  const double carried = chains::momentum(model, model.velocity.cwiseAbs());
  return std::abs(chains::momentum(model, impact.velocity_after) - before) / carried;
}

inline double kinetic_energy_ratio(const chains::ChainModel& model,
                                   const granular::ImpactOutcome& impact) {
  return granular::kinetic_energy(model, impact.velocity_after) /
         granular::kinetic_energy(model, model.velocity);
}

// ||a - b||_inf / ||b||_inf, the discrepancy of Nguyen & Brogliato (2011), eq. 47.
inline double relative_difference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

inline Eigen::VectorXd stiffnesses(const chains::ChainModel& model) {
  Eigen::VectorXd k(model.contact_count());
  for (Eigen::Index i = 0; i < k.size(); ++i) k(i) = model.laws[i].stiffness;
  return k;
}

}  // namespace mimpact::testing
