#include <cmath>
#include <iostream>
#include <map>
#include <optional>

#include "command_line.hpp"
#include "commands.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/packings/packing_run.hpp"
#include "output_directory.hpp"

namespace mimpact::cli {

namespace po = boost::program_options;

namespace {

// Everything a run writes into --out: complete or not at all.
std::map<std::string, std::string> output_files(const nlohmann::ordered_json& summary,
                                                const packings::PackingModel& model,
                                                const granular::SceneRun& run) {
  std::map<std::string, std::string> files{{"summary.json", summary.dump(2) + "\n"},
                                           {"bodies.csv", packings::bodies_csv(model)},
                                           {"contacts.csv", packings::contacts_csv(model)}};
  if (run.recorded && !run.series.contacts.empty()) files["forces.csv"] = run.series.forces_csv();
  if (run.recorded && !run.series.bodies.empty())
    files["velocities.csv"] = run.series.velocities_csv();
  if (!run.frames.empty()) {
    files["frame_forces.csv"] = packings::frame_forces_csv(run.frames);
    files["frame_velocities.csv"] = packings::frame_velocities_csv(run.frames, model.dimension);
    if (!run.frames.position.empty())
      files["frame_positions.csv"] = packings::frame_positions_csv(run.frames, model.dimension);
    if (!run.frames.angular_velocity.empty())
      files["frame_angular_velocities.csv"] =
          packings::frame_angular_velocities_csv(run.frames, model.dimension);
  }
  return files;
}

}  // namespace

int packing_command(const std::vector<std::string>& arguments) {
  std::string scene_file, out_dir;
  granular::RunLimits limits;
  po::options_description visible(
      "mimpact packing SCENE.json: the multiple impact of a packing of beads, in the plane or in "
      "space");
  visible.add_options()(
      "out", po::value(&out_dir),
      "write summary.json, bodies.csv, contacts.csv and the recorded series and frames into this "
      "directory instead of summary.json on stdout")(
      "delta-p", po::value<double>(), "principal impulse step (N s); overrides impact.delta_p")(
      "data-dir", po::value<std::string>(),
      "the directory bead lists are read from (and only from): the scene file's by default")(
      "max-memory", po::value(&limits.memory_gb),
      "GB the run may hold (the packing, its series and frames), 4 by default; a run that needs "
      "more is refused before it starts")("quiet", "no report on stderr");
  add_accuracy_options(visible);
  add_run_limit_options(visible, limits);
  po::variables_map values;
  if (!parse_command_line(arguments, visible, "scene", scene_file, values)) return 0;
  const bool quiet = values.count("quiet") > 0;
  limits.check();
  const std::filesystem::path out =
      values.count("out") ? check_output_directory(out_dir) : std::filesystem::path();

  packings::PackingScene scene = packings::load_packing_scene(scene_file);
  if (values.count("data-dir")) scene.directory = values["data-dir"].as<std::string>();
  const packings::PackingModel model = packings::build_packing_model(scene, limits);
  granular::ImpactOverrides overrides{.delta_p_name = "--delta-p"};
  if (values.count("delta-p")) overrides.delta_p = values["delta-p"].as<double>();
  granular::SceneRunOptions run_options;
  read_accuracy_options(values, overrides, run_options);
  const bool recording =
      !scene.record.contacts.empty() || !scene.record.beads.empty() || scene.record.frames > 0;
  if (recording && out.empty() && !quiet)
    std::cerr << "mimpact packing: \"record\" needs --out DIR to write its series; ignored\n";
  run_options.impact = overrides;
  run_options.record = recording && !out.empty();
  run_options.limits = limits;
  const std::unique_ptr<granular::ProgressMeter> progress = progress_line(quiet, limits);
  run_options.progress = progress.get();
  const granular::SceneRun run = packings::run_packing_scene(scene, model, run_options);
  if (progress) progress->finish();
  const nlohmann::ordered_json summary = packings::packing_summary(model, run);
  if (!quiet) std::cerr << scene_file << ": " << packings::packing_report(model, run);
  if (run.configuration_fails())  // even when quiet: the model is wrong
    std::cerr << scene_file << ": warning: " << run.configuration->describe() << "\n";
  if (run.impact.result.status != numerics::ImpactStatus::terminated)
    throw Error(scene_file + ": " + run.impact.result.message + "; no output written");
  if (!(run.impact.velocity_after.allFinite() && run.impact.result.max_force.allFinite() &&
        std::isfinite(run.impact.result.duration)))
    throw Error(scene_file +
                ": the run produced a non-finite velocity, force or duration; no output written");
  if (out.empty()) {
    std::cout << summary.dump(2) << "\n";
    return 0;
  }
  write_output_directory(out, output_files(summary, model, run));
  return 0;
}

}  // namespace mimpact::cli
