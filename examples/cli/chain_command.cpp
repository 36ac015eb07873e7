#include <unistd.h>

#include <boost/program_options.hpp>
#include <cstdio>
#include <iostream>
#include <optional>

#include "command_line.hpp"
#include "commands.hpp"
#include "mimpact/chain/chain_impact.hpp"
#include "mimpact/numerics/error.hpp"
#include "output_directory.hpp"

namespace mimpact::cli {

namespace po = boost::program_options;

namespace {

// Reports the impulse steps on stderr while a long impact runs.
class ProgressReporter : public numerics::ImpactObserver {
 public:
  void observe(const numerics::ImpactSample& sample) override {
    if (sample.step == 0) return;
    std::fprintf(stderr, "\r  %lld impulse steps, t = %.6g s", (long long)sample.step, sample.time);
    std::fflush(stderr);
    reported_ = true;
  }
  ~ProgressReporter() override {
    if (reported_) std::fputc('\n', stderr);
  }

 private:
  bool reported_ = false;
};

}  // namespace

int chain_command(const std::vector<std::string>& arguments) {
  std::string scene_file, out_dir;
  std::optional<double> delta_p_option;
  po::options_description visible(
      "mimpact chain SCENE.json: the multiple impact of a granular chain");
  visible.add_options()(
      "out", po::value(&out_dir), "write summary.json into this directory instead of stdout")(
      "delta-p", po::value<double>(), "principal impulse step (N s); overrides impact.delta_p")(
      "quiet", "no progress or report on stderr");
  po::variables_map values;
  if (!parse_command_line(arguments, visible, "scene", scene_file, values)) return 0;
  const bool quiet = values.count("quiet") > 0;

  const chain::ChainScene scene = chain::load_chain_scene(scene_file);
  if (values.count("delta-p")) delta_p_option = values["delta-p"].as<double>();
  const std::optional<double> delta_p = delta_p_option ? delta_p_option : scene.delta_p;
  if (!delta_p)
    throw InvalidInput(scene_file + ": missing field impact.delta_p (or give --delta-p)");

  numerics::LzbOptions options;
  options.delta_p = *delta_p;
  std::string why;
  if (!options.is_valid(&why)) throw InvalidInput("--delta-p: " + why);
  const bool show_progress = !quiet && isatty(STDERR_FILENO);
  ProgressReporter progress;
  if (show_progress) {
    options.sample_every = 2'000'000;
    options.sampled_contacts = {0};
  }

  const chain::ChainModel model = chain::build_chain_model(scene);
  const chain::ChainImpact impact =
      chain::simulate_chain_impact(model, options, show_progress ? &progress : nullptr);
  const nlohmann::ordered_json summary = chain::chain_summary(model, impact, *delta_p);

  if (!quiet)
    std::cerr << scene_file << ": " << chain::chain_report(model, impact, *delta_p);
  if (impact.lzb.status != numerics::LzbStatus::terminated)
    throw Error(scene_file + ": " + impact.lzb.message + "; no output written");
  if (out_dir.empty()) {
    std::cout << summary.dump(2) << "\n";
  } else {
    write_output_directory(out_dir, {{"summary.json", summary.dump(2) + "\n"}});
  }
  return 0;
}

}  // namespace mimpact::cli
