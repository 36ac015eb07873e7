#include <boost/program_options.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <optional>

#include "command_line.hpp"
#include "commands.hpp"
#include "convergence_report.hpp"
#include "mimpact/chains/chain_convergence.hpp"
#include "mimpact/chains/chain_impact.hpp"
#include "mimpact/chains/chain_run.hpp"
#include "mimpact/common/error.hpp"
#include "output_directory.hpp"

namespace mimpact::cli {

namespace po = boost::program_options;

namespace {

// LZB's relative error is 1 to 13 times delta_p / (m V) on the chains of docs/performance.md:
// past 1 % of the striker's momentum the outcome is off by percents.
void warn_if_coarse(double delta_p, double striker_momentum, bool quiet) {
  const double share = delta_p / striker_momentum;
  if (quiet || !(share > 1e-2)) return;
  std::fprintf(
      stderr,
      "mimpact chain: warning: delta_p = %g N s is %.3g of the striker's momentum m V = %g N s; "
      "the outcome may be off by %.3g %% or more; take delta_p <= 1e-3 m V or use --tolerance\n",
      delta_p, share, striker_momentum, 100.0 * share);
}

// summary.json on stdout, or with the time series into `out`, complete or not at all.
void write_results(const nlohmann::ordered_json& summary, const granular::TimeSeries* series,
                   const std::filesystem::path& out) {
  if (out.empty()) {
    std::cout << summary.dump(2) << "\n";
    return;
  }
  std::map<std::string, std::string> files{{"summary.json", summary.dump(2) + "\n"}};
  if (series) {
    if (!series->contacts.empty()) files["forces.csv"] = series->forces_csv();
    if (!series->bodies.empty()) files["velocities.csv"] = series->velocities_csv();
  }
  write_output_directory(out, files);
}

// --tolerance: what to meet, from which delta_p, within which memory, for which scene file
struct ToleranceRequest {
  const std::vector<double>& tolerance;
  std::optional<double> first;  // N s, --delta-p
  const granular::RunLimits& limits;
  const std::string& scene_file;
};

// the study that chose the scene's step rule: over the adaptive integrator's tolerance or
// over delta_p (neither without --tolerance)
struct Studies {
  std::optional<analysis::ConvergenceStudy> delta_p;
  std::optional<analysis::ToleranceStudy> tolerance;
};

// Runs the study --tolerance asks for and sets the scene's tolerance or delta_p to the one that
// met it; throws Error, naming the scene file, when none does.
Studies meet_tolerance(chains::ChainScene& scene, const chains::ChainModel& model,
                       const ToleranceRequest& request) {
  Studies studies;
  const std::string& scene_file = request.scene_file;
  if (request.tolerance.empty()) return studies;
  if (!request.first && chains::uses_tolerance_study(scene)) {
    studies.tolerance = analysis::study_tolerance(
        chains::impact_problem(model),
        chains::tolerance_study_options(
            scene, {.tolerance = request.tolerance, .max_rows = 8, .limits = request.limits}));
    const analysis::ToleranceStudy& study = *studies.tolerance;
    if (!study.converged)
      throw Error(scene_file + ": no tolerance down to " + to_text(study.finest_tolerance) +
                  " met --tolerance; loosen it; no output written");
    scene.impact.integrator = plugins::LzbIntegrator::adaptive;
    scene.impact.tolerance = study.finest_tolerance;
    return studies;
  }
  studies.delta_p = analysis::study_convergence(
      chains::impact_problem(model), chains::convergence_options(scene, model,
                                                                 {.tolerance = request.tolerance,
                                                                  .first = request.first,
                                                                  .max_rows = 12,
                                                                  .first_name = "--delta-p",
                                                                  .limits = request.limits}));
  const analysis::ConvergenceStudy& study = *studies.delta_p;
  if (!study.converged && !study.stopped.empty())
    throw Error(scene_file + ": --tolerance not met: " + study.stopped + "; no output written");
  if (!study.converged)
    throw Error(scene_file + ": no delta_p down to " + to_text(study.rows.back().delta_p) +
                " N s met --tolerance; loosen it or start smaller; no output written");
  scene.impact.delta_p = study.rows.back().delta_p;
  scene.impact.relative_delta_p.reset();
  return studies;
}

}  // namespace

int chain_command(const std::vector<std::string>& arguments) {
  std::string scene_file, out_dir;
  granular::RunLimits limits;
  std::vector<double> tolerance;
  po::options_description visible(
      "mimpact chain SCENE.json: the multiple impact of a granular chain");
  visible.add_options()("out", po::value(&out_dir),
                        "write summary.json into this directory instead of stdout")(
      "delta-p", po::value<double>(), "principal impulse step (N s); overrides impact.delta_p")(
      "tolerance", po::value(&tolerance)->multitoken(),
      "eps+ [eps]: meet this accuracy: with the adaptive integrator (a scene with \"integrator\": "
      "\"adaptive\", or neither delta_p nor an integrator), divide its tolerance by 10 until the "
      "post-impact velocities (and the peak forces) change by at most eps+ (eps) relative; with "
      "the impulse steps, halve delta_p from --delta-p (or the scene's, or 1e-3 of the striker's "
      "m V) until the velocities (and those along the impact) do; see `mimpact converge`")(
      "max-memory", po::value(&limits.memory_gb),
      "GB the run may hold (the chain and its recorded series), 4 by default; a run that needs "
      "more is refused before it starts")("quiet", "no progress or report on stderr");
  add_accuracy_options(visible);
  add_run_limit_options(visible, limits);
  po::variables_map values;
  if (!parse_command_line(arguments, visible, "scene", scene_file, values)) return 0;
  const bool quiet = values.count("quiet") > 0;
  limits.check();
  const std::filesystem::path out =
      values.count("out") ? check_output_directory(out_dir) : std::filesystem::path();

  chains::ChainScene scene = chains::load_chain_scene(scene_file);
  const chains::ChainModel model = chains::build_chain_model(scene, limits);
  granular::ImpactOverrides overrides{.delta_p_name = "--delta-p"};
  if (values.count("delta-p")) overrides.delta_p = values["delta-p"].as<double>();
  granular::SceneRunOptions run_options;
  read_accuracy_options(values, overrides, run_options);
  scene.accuracy = granular::resolve_accuracy(scene.accuracy, overrides);
  if (scene.accuracy && !tolerance.empty())
    throw InvalidInput("--tolerance beside accuracy = " + to_text(*scene.accuracy) +
                       ": the accuracy chooses the step; allowed: one of them");
  scene.impact =
      granular::resolve_impact(scene.impact, scene.method, overrides, scene_file, scene.accuracy);
  const bool lzb = scene.method == granular::Method::lzb;
  const Studies studies = meet_tolerance(scene, model,
                                         {.tolerance = tolerance,
                                          .first = overrides.delta_p,
                                          .limits = limits,
                                          .scene_file = scene_file});
  const bool recording = !scene.record.contacts.empty() || !scene.record.bodies.empty();
  if (recording && out.empty() && !quiet)
    std::cerr << "mimpact chain: \"record\" needs --out DIR to write its time series; ignored\n";
  const bool writes_series = recording && !out.empty();

  if (lzb && !scene.adaptive() && !scene.accuracy) {  // refused before it is warned of
    const double delta_p =
        granular::impulse_step(model, scene.impact, granular::impact_labels(overrides));
    warn_if_coarse(delta_p, granular::smallest_momentum(model), quiet);
  }
  run_options.record = writes_series;
  run_options.limits = limits;
  const std::unique_ptr<granular::ProgressMeter> progress = progress_line(quiet, limits);
  run_options.progress = progress.get();
  granular::SceneRun run = chains::run_chain_scene(scene, model, run_options);
  if (progress) progress->finish();
  const granular::ImpactOutcome& impact = run.impact;
  const granular::TimeSeries& series = run.series;
  nlohmann::ordered_json summary = chains::run_summary(model, run);
  if (studies.delta_p) summary["convergence"] = chains::convergence_json(*studies.delta_p);
  if (studies.tolerance) summary["convergence"] = chains::tolerance_json(*studies.tolerance);

  if (!quiet)
    std::cerr << scene_file << ": "
              << chains::chain_report(model, impact, granular::describe_method(run))
              << granular::describe_error(run);
  if (impact.result.status != numerics::ImpactStatus::terminated)
    throw Error(scene_file + ": " + impact.result.message + "; no output written");
  if (!(impact.velocity_after.allFinite() && impact.result.max_force.allFinite() &&
        std::isfinite(impact.result.duration)))
    throw Error(scene_file +
                ": the run produced a non-finite velocity, force or duration; no output written");
  write_results(summary, writes_series ? &series : nullptr, out);
  return 0;
}

}  // namespace mimpact::cli
