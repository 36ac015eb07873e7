// The energy ledger of summary.json (issue 11): kinetic_before + potential_before +
// work_of_forces = kinetic_after + dissipated_total + potential_left to round-off, for every
// method and every kind of scene, with the dissipation where the contact laws put it. The
// round-off is that of the velocities carried from step to step: at most a machine epsilon of
// the energy per step (measured: 2.6e-17 per step on C1's 45 920 impulse steps).
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "mimpact/chains/chain_run.hpp"

namespace mimpact::testing {
namespace {

using nlohmann::json;

json read_scene(const std::string& name) {
  std::ifstream in(std::string(MIMPACT_SOURCE_DIR) + "/examples/scenes/" + name);
  std::stringstream text;
  text << in.rdbuf();
  return json::parse(text.str(), nullptr, true, /*ignore_comments=*/true);
}

enum class Method { impulse_steps, adaptive, compliant };

const char* method_name(Method method) {
  switch (method) {
    case Method::impulse_steps:
      return "impulse steps";
    case Method::adaptive:
      return "adaptive";
    default:
      return "compliant";
  }
}

// The scene run by `method`: its own delta_p, the adaptive LZB at 1e-8 or the compliant
// method at 1e-10 (until end_time when the scene gives one).
granular::EnergyLedger ledger_of(json scene, Method method, const std::string& what) {
  scene.erase("record");
  if (method == Method::adaptive)
    scene["impact"] = {{"integrator", "adaptive"}, {"tolerance", 1e-8}};
  if (method == Method::compliant) {
    scene.erase("impact");
    scene["method"] = "compliant";
    if (!scene.contains("compliant")) scene["compliant"] = json::object();
    scene["compliant"]["tolerance"] = 1e-10;
  }
  const chains::ChainScene parsed = chains::parse_chain_scene(scene.dump(), what);
  const chains::ChainModel model = chains::build_chain_model(parsed);
  const granular::SceneRun run = chains::run_chain_scene(parsed, model);
  const granular::EnergyLedger ledger = granular::energy_ledger(model, run.impact);
  const double scale = ledger.kinetic_before + ledger.potential_before + ledger.work_of_forces;
  std::printf("%-40s %-14s T %.6g -> %.6g J, dissipated %.4g, left %.3g, imbalance %.2g\n",
              what.c_str(), method_name(method), ledger.kinetic_before, ledger.kinetic_after,
              ledger.dissipated_total, ledger.potential_left, ledger.imbalance() / scale);
  const double steps = double(std::max<std::int64_t>(run.impact.result.steps, 100));
  EXPECT_LE(std::abs(ledger.imbalance()), steps * DBL_EPSILON * scale)
      << what << ", " << method_name(method);
  EXPECT_EQ(ledger.dissipated.size(), model.contact_count());
  return ledger;
}

const Method kMethods[] = {Method::impulse_steps, Method::adaptive, Method::compliant};

// Elastic contacts (e = 1) dissipate nothing but what the method's accuracy leaves.
TEST(EnergyLedger, ElasticChainDissipatesNothing) {
  for (Method method : kMethods) {
    const granular::EnergyLedger ledger = ledger_of(read_scene("c1.json"), method, "c1.json");
    EXPECT_LE(std::abs(ledger.dissipated_total), 1e-6 * ledger.kinetic_before);
    EXPECT_LE(ledger.potential_left, 1e-6 * ledger.kinetic_before);
  }
}

// e = 0.6: the kinetic energy lost is dissipated, every contact's share >= 0, and the
// adaptive LZB and the impulse steps (the same model) put it at the same contacts.
TEST(EnergyLedger, DissipationIsWhereTheLawsPutIt) {
  const json scene = read_scene("c3.json");
  const granular::EnergyLedger steps = ledger_of(scene, Method::impulse_steps, "c3.json");
  const granular::EnergyLedger adaptive = ledger_of(scene, Method::adaptive, "c3.json");
  ledger_of(scene, Method::compliant, "c3.json");
  const double lost = steps.kinetic_before - steps.kinetic_after;
  EXPECT_GT(lost, 0.1 * steps.kinetic_before);
  EXPECT_GE(steps.dissipated.minCoeff(), -1e-12 * lost);
  EXPECT_GE(adaptive.dissipated.minCoeff(), -1e-12 * lost);
  // the scene's delta_p (1e-6 N s) is first order: a few 1e-5 of the energy
  EXPECT_LE((steps.dissipated - adaptive.dissipated).cwiseAbs().maxCoeff(), 1e-4 * lost);
}

// A lone contact: the energy lost is (1 - e^2) of the kinetic energy of the relative motion,
// m1 m2 / (m1 + m2) V^2 / 2, all of it dissipated at that contact.
TEST(EnergyLedger, LoneContactDissipatesOneMinusESquared) {
  json scene = read_scene("c1.json");
  scene["chain"]["segments"][0]["count"] = 1;
  scene["contact"]["restitution"] = 0.5;
  for (Method method : kMethods) {
    const granular::EnergyLedger ledger = ledger_of(scene, method, "striker and one bead, e = 0.5");
    // equal masses: the relative motion holds half the kinetic energy
    const double expected = (1.0 - 0.25) * 0.5 * ledger.kinetic_before;
    EXPECT_NEAR(ledger.dissipated(0), expected, 1e-5 * expected) << method_name(method);
  }
}

// The other kinds of scenes: strikers from both ends, a wall, a striker flying to the chain,
// and a precompressed chain, whose static load holds potential energy and does work.
TEST(EnergyLedger, EveryKindOfScene) {
  for (Method method : kMethods) {
    ledger_of(read_scene("paper/s25_collision.json"), method, "s25_collision.json (two strikers)");
    ledger_of(read_scene("paper/scaling_wall_e0965.json"), method, "scaling_wall_e0965.json");
    json flying = read_scene("c3.json");
    flying["strikers"][0]["gap"] = 1e-3;
    ledger_of(flying, method, "c3.json, striker 1 mm away");
  }
  const granular::EnergyLedger precompressed =
      ledger_of(read_scene("paper/coste_chain_precompressed.json"), Method::compliant,
                "coste_chain_precompressed.json");
  EXPECT_GT(precompressed.potential_before, 0.0);
  EXPECT_NE(precompressed.work_of_forces, 0.0);
}

}  // namespace
}  // namespace mimpact::testing
