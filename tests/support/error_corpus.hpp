#pragma once

// The corpus of scenes on which a run's estimate of its own error is judged (issue 48;
// tests/data/error_corpus/corpus.json): its scenes, their runs, and the true error of a run
// against the same scene at a step 1 000 times finer. Read by the corpus test
// (tests/packings/test_error_corpus.cpp) and the accuracy benchmark (bench/bench_accuracy.cpp).

#include <Eigen/Dense>
#include <algorithm>
#include <fstream>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "mimpact/chains/chain_model.hpp"
#include "mimpact/chains/chain_run.hpp"
#include "mimpact/chains/chain_scene.hpp"
#include "mimpact/granular/error_estimate.hpp"
#include "mimpact/granular/scene_run.hpp"
#include "mimpact/numerics/lzb_adaptive_options.hpp"
#include "mimpact/packings/packing_model.hpp"
#include "mimpact/packings/packing_run.hpp"
#include "mimpact/packings/packing_scene.hpp"

namespace mimpact::testing {

struct CorpusScene {
  std::string name;
  nlohmann::json scene;  // whole: the corpus's defaults with the scene's patch merged in
};

// The corpus's scenes, in its file's order.
inline std::vector<CorpusScene> error_corpus(const std::string& source_dir) {
  const std::string path = source_dir + "/tests/data/error_corpus/corpus.json";
  std::ifstream file(path);
  if (!file) throw std::runtime_error("cannot read " + path);
  const nlohmann::json corpus = nlohmann::json::parse(file, nullptr, true, true);
  std::vector<CorpusScene> scenes;
  for (nlohmann::json patch : corpus.at("scenes")) {
    nlohmann::json scene = corpus.at(patch.contains("lattice") ? "packing" : "chain");
    const std::string name = patch.at("name");
    patch.erase("name");
    scene.merge_patch(patch);
    scenes.push_back({name, scene});
  }
  return scenes;
}

// A scene read and its model built: run() runs it.
struct CorpusCase {
  std::shared_ptr<const granular::ContactModel> model;  // a chain's or a packing's
  std::function<granular::SceneRun(const granular::SceneRunOptions&)> run;
};

inline CorpusCase prepare_corpus_scene(const nlohmann::json& scene, const std::string& name) {
  if (scene.contains("lattice")) {
    auto parsed =
        std::make_shared<packings::PackingScene>(packings::read_packing_scene(scene, name, "."));
    auto model = std::make_shared<packings::PackingModel>(packings::build_packing_model(*parsed));
    return {model, [parsed, model](const granular::SceneRunOptions& options) {
              return packings::run_packing_scene(*parsed, *model, options);
            }};
  }
  auto parsed = std::make_shared<chains::ChainScene>(chains::read_chain_scene(scene, name));
  auto model = std::make_shared<chains::ChainModel>(chains::build_chain_model(*parsed));
  return {model, [parsed, model](const granular::SceneRunOptions& options) {
            return chains::run_chain_scene(*parsed, *model, options);
          }};
}

// A scene's model and its run.
struct CorpusRun {
  std::shared_ptr<const granular::ContactModel> model;
  granular::SceneRun run;
};

inline CorpusRun run_corpus_scene(const nlohmann::json& scene, const std::string& name,
                                  const granular::SceneRunOptions& options) {
  const CorpusCase prepared = prepare_corpus_scene(scene, name);
  return {prepared.model, prepared.run(options)};
}

// The scene at its step rule made 1 000 times finer; the impulse steps' at their limit as
// delta_p goes to zero, the adaptive LZB at `impulse_limit` (docs/model.md, section 10).
inline nlohmann::json finer_by_1000(nlohmann::json scene, double impulse_limit = 1e-11) {
  const double lzb_finest = numerics::LzbAdaptiveOptions::kToleranceRange.lower;
  if (scene.value("method", "lzb") == "compliant") {
    nlohmann::json& compliant = scene["compliant"];
    compliant["tolerance"] = compliant["tolerance"].get<double>() / 1000.0;
    // a fifth-order pair takes 1 000^(1/5), about 4 times the steps
    compliant["max_steps"] = 4 * compliant.value("max_steps", granular::CompliantSpec{}.max_steps);
  } else if (scene.value("impact", nlohmann::json::object()).value("integrator", "") ==
             "adaptive") {
    double& tolerance = scene["impact"]["tolerance"].get_ref<double&>();
    tolerance = std::max(tolerance / 1000.0, lzb_finest);
  } else {
    scene["impact"] = {{"integrator", "adaptive"}, {"tolerance", impulse_limit}};
  }
  return scene;
}

// The true error of `velocity` against `exact`, as the estimate states its own (of the fastest
// speed before the impact: the worst body and the RMS).
inline granular::ErrorEstimate error_against(const granular::ContactModel& model,
                                             const Eigen::VectorXd& velocity,
                                             const Eigen::VectorXd& exact) {
  return granular::estimate_error(model, velocity, exact, {.scale = 1.0, .method = "true"});
}

}  // namespace mimpact::testing
