#include <boost/program_options.hpp>
#include <iostream>
#include <optional>

#include "command_line.hpp"
#include "commands.hpp"
#include "convergence_report.hpp"
#include "mimpact/chains/chain_convergence.hpp"

namespace mimpact::cli {

namespace po = boost::program_options;

int converge_command(const std::vector<std::string>& arguments) {
  std::string scene_file;
  int halvings = 12;
  granular::RunLimits limits;
  std::vector<double> tolerance;
  po::options_description visible(
      "mimpact converge SCENE.json: delta_p = h, h/2, h/4, ... until the LZB impact converges "
      "(Nguyen & Brogliato 2011, appendix A.2), or, for a scene with \"integrator\": "
      "\"adaptive\" or neither delta_p nor an integrator, the adaptive integrator's tolerance "
      "t, t/10, t/100, ...; exit status 4 when it does not converge within the rows");
  visible.add_options()(
      "from", po::value<double>(),
      "the first delta_p h (N s; default: the scene's, else 1e-3 of the striker's m V), or the "
      "first tolerance t (default: the scene's, else the smallest of eps+ and eps)")(
      "tolerance", po::value(&tolerance)->multitoken(),
      "eps+ [eps]: bounds on eta+ (post-impact velocities) and on max eta_h (along the impact) or "
      "the peak forces' change (tolerance study); default 0.01 0.01")(
      "halvings", po::value(&halvings)->default_value(halvings), "at most this many rows")(
      "max-memory", po::value(&limits.memory_gb),
      "GB the study may hold (the steps of two runs compared along the impact), 4 by default")(
      "json", "print one JSON object instead of the table");
  po::variables_map values;
  if (!parse_command_line(arguments, visible, "scene", scene_file, values)) return 0;
  limits.check();
  const chains::ChainScene scene = chains::load_chain_scene(scene_file);
  const chains::ChainModel model = chains::build_chain_model(scene, limits);
  chains::StudyRequest request{.tolerance = tolerance, .max_rows = halvings, .limits = limits};
  if (values.count("from")) request.first = values["from"].as<double>();
  if (chains::uses_tolerance_study(scene)) {
    const analysis::ToleranceStudy study = analysis::study_tolerance(
        chains::impact_problem(model), chains::tolerance_study_options(scene, request));
    if (values.count("json"))
      std::cout << chains::tolerance_json(study).dump(2) << "\n";
    else
      print_tolerance_table(study);
    return study.converged ? 0 : 4;
  }
  const analysis::ConvergenceStudy study = analysis::study_convergence(
      chains::impact_problem(model), chains::convergence_options(scene, model, request));
  if (values.count("json"))
    std::cout << chains::convergence_json(study).dump(2) << "\n";
  else
    print_convergence_table(study);
  return study.converged ? 0 : 4;
}

}  // namespace mimpact::cli
