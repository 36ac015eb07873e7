// Issue 48's honesty: over the corpus (tests/data/error_corpus/corpus.json: chains of 20 to
// 100 000 beads with walls, tapers and precompression; hexagonal, square, FCC and HCP packings of
// 100 to 10 648 beads; e = 1, 0.9, 0.5; the impulse steps, the adaptive LZB and the compliant
// method), a run's estimate of its error (granular/error_estimate.hpp) bounds the true error,
// against the same scene at a step 1 000 times finer, in at least 95 % of the runs, and is
// within ten times it in at least 90 %: of the worst body, the figure an accuracy asks for.
// Chains and packings both, so it links both.
#include <gtest/gtest.h>

#include <cstdio>
#include <set>
#include <string>

#include "../support/error_corpus.hpp"

namespace mimpact::testing {
namespace {

// How a scene is run, in the corpus's words.
std::string method_of(const nlohmann::json& scene) {
  if (scene.value("method", "lzb") == "compliant") return "compliant";
  return scene["impact"].value("integrator", "") == "adaptive" ? "adaptive" : "impulse steps";
}

TEST(ErrorCorpus, SpansTheScenesTheIssueNames) {
  std::set<std::string> methods, lattices, walls;
  std::set<double> restitutions;
  int fewest = 1 << 30, most = 0;
  const std::vector<CorpusScene> corpus = error_corpus(MIMPACT_SOURCE_DIR);
  for (const CorpusScene& entry : corpus) {
    const nlohmann::json& scene = entry.scene;
    methods.insert(method_of(scene));
    restitutions.insert(scene["contact"]["restitution"].get<double>());
    if (scene.contains("lattice")) lattices.insert(scene["lattice"]["type"].get<std::string>());
    if (scene.contains("wall")) walls.insert("wall");
    if (scene.contains("precompression")) walls.insert("precompression");
    if (scene.contains("chain") && scene["chain"]["segments"][0].contains("taper"))
      walls.insert("taper");
    if (scene.contains("chain")) {
      const int count = scene["chain"]["segments"][0]["count"];
      fewest = std::min(fewest, count);
      most = std::max(most, count);
    }
  }
  EXPECT_GE(corpus.size(), 40u);
  EXPECT_EQ(methods, (std::set<std::string>{"adaptive", "compliant", "impulse steps"}));
  EXPECT_EQ(lattices, (std::set<std::string>{"fcc", "hcp", "hexagonal", "square"}));
  EXPECT_EQ(walls, (std::set<std::string>{"precompression", "taper", "wall"}));
  EXPECT_EQ(restitutions, (std::set<double>{0.5, 0.9, 1.0}));
  EXPECT_EQ(fewest, 20);
  EXPECT_EQ(most, 100'000);
}

TEST(ErrorCorpus, TheEstimateBoundsTheTrueErrorAndIsWithinTenTimesIt) {
  const std::vector<CorpusScene> corpus = error_corpus(MIMPACT_SOURCE_DIR);
  int bounded = 0, within_ten = 0, rms_bounded = 0, rms_within_ten = 0;
  std::printf("%-46s %10s %10s %8s %8s\n", "scene", "estimate", "true", "ratio", "RMS ratio");
  for (const CorpusScene& entry : corpus) {
    const CorpusRun run =
        run_corpus_scene(entry.scene, entry.name, {.record = false, .estimate_error = true});
    const CorpusRun exact =
        run_corpus_scene(finer_by_1000(entry.scene), entry.name, {.record = false});
    ASSERT_TRUE(run.run.error_estimate) << entry.name;
    const granular::ErrorEstimate& estimate = *run.run.error_estimate;
    const granular::ErrorEstimate truth =
        error_against(*run.model, run.run.impact.velocity_after, exact.run.impact.velocity_after);
    bounded += truth.worst <= estimate.worst;
    within_ten += estimate.worst <= 10.0 * truth.worst;
    rms_bounded += truth.rms <= estimate.rms;
    rms_within_ten += estimate.rms <= 10.0 * truth.rms;
    std::printf("%-46s %10.3g %10.3g %8.3g %8.3g\n", entry.name.c_str(), estimate.worst,
                truth.worst, estimate.worst / truth.worst, estimate.rms / truth.rms);
    std::fflush(stdout);
  }
  const double runs = double(corpus.size());
  std::printf("worst body: bounded in %d, within ten times in %d of %d runs; RMS: %d and %d\n",
              bounded, within_ten, int(corpus.size()), rms_bounded, rms_within_ten);
  EXPECT_GE(bounded, 0.95 * runs);
  EXPECT_GE(within_ten, 0.90 * runs);
}

}  // namespace
}  // namespace mimpact::testing
