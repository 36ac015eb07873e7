// An application on the installed package that links the chains library: a scene given as
// text, the impact computed through the kernel, the summary printed as JSON. Exits non-zero
// when the chain's momentum is not conserved.
#include <cmath>
#include <cstdio>
#include <mimpact/chains/chain_impact.hpp>
#include <mimpact/chains/chain_model.hpp>
#include <mimpact/chains/chain_scene.hpp>

using namespace mimpact;

int main() {
  // ten steel beads struck by an eleventh at 1 m/s, elastic Hertz contacts
  const chains::ChainScene scene = chains::parse_chain_scene(
      R"({"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
          "chain": {"segments": [{"count": 10, "radius": 0.01}]},
          "strikers": [{"radius": 0.01, "velocity": 1.0}],
          "impact": {"delta_p": 1e-6}})",
      "inline scene");
  const chains::ChainModel model = chains::build_chain_model(scene);
  const granular::ImpactOutcome impact = chains::simulate_chain_impact(model, scene.impact);
  std::printf("%s\n", chains::chain_summary(model, impact, scene.impact.delta_p).dump(2).c_str());
  const double before = chains::momentum(model, model.velocity);
  const double after = chains::momentum(model, impact.velocity_after);
  return std::abs(after - before) <= 1e-12 * std::abs(before) ? 0 : 1;
}
