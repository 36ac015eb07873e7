#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Eigen/Dense>
#include <filesystem>
#include <optional>
#include <string>

#include "bindings.hpp"
#include "json_conversion.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/packings/packing_run.hpp"
#include "scene_arguments.hpp"
#include "scene_result.hpp"

namespace py = pybind11;

namespace mimpact::python {

namespace {

// What run_packing() returns: the vectors of summary.json as arrays, the series and frames.
// Per body a row of `dimension` components.
struct PackingResult : SceneResult {
  Eigen::MatrixXd post_impact_velocities;  // m/s, per body (beads, then strikers)
  // rad/s, per body: a column (about z) in the plane, three in space; zeros when nothing turns
  Eigen::MatrixXd post_impact_angular_velocities;
  Eigen::MatrixXd body_impulses;            // N s, per body
  Eigen::MatrixXd positions;                // m, the centres, per body
  Eigen::VectorXd radii;                    // m, per body
  Eigen::MatrixX2i contact_bodies;          // the two bodies of each contact (-1: a wall)
  std::optional<double> contacts_per_step;  // the LZB integrators'; None for the compliant
  // dict: time, forces (frames x contacts), velocities, and in the moving geometry positions
  py::object frames = py::none();
};

packings::PackingScene load_scene(const py::object& scene) {
  return load_scene_argument(
      scene,
      [](nlohmann::json document) {
        return packings::read_packing_scene(std::move(document), "scene",
                                            std::filesystem::current_path());
      },
      [](const std::string& path) { return packings::load_packing_scene(path); });
}

// a row of `dimension` components per body
Eigen::MatrixXd per_body(const Eigen::VectorXd& coordinates, int dimension) {
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      coordinates.data(), coordinates.size() / dimension, dimension);
}

py::dict frames_dict(const granular::Frames& frames, Eigen::Index bodies, int dimension) {
  py::dict dict;
  dict["time"] = Eigen::VectorXd(
      Eigen::Map<const Eigen::VectorXd>(frames.time.data(), Eigen::Index(frames.time.size())));
  dict["forces"] = table(frames.force, frames.force.empty() ? 0 : frames.force.front().size());
  const auto per_frame = [&](const std::vector<std::vector<double>>& rows, int components) {
    return py::module_::import("numpy")
        .attr("asarray")(table(rows, std::size_t(components * bodies)))
        .attr("reshape")(Eigen::Index(frames.time.size()), bodies, components);
  };
  dict["velocities"] = per_frame(frames.velocity, dimension);
  // when the bodies turn: (frames, bodies, 1) about z in the plane, (frames, bodies, 3) in space
  if (!frames.angular_velocity.empty())
    dict["angular_velocities"] = per_frame(frames.angular_velocity, dimension == 3 ? 3 : 1);
  // the moving geometry's: where the bodies are at each frame
  if (!frames.position.empty()) dict["positions"] = per_frame(frames.position, dimension);
  return dict;
}

PackingResult run_packing(const py::object& scene_argument, std::optional<double> delta_p,
                          std::optional<double> accuracy, bool estimate_error,
                          const py::object& data_dir, double max_memory,
                          std::optional<double> max_seconds, int threads, bool progress) {
  packings::PackingScene scene = load_scene(scene_argument);
  if (!data_dir.is_none())
    scene.directory = py::module_::import("os").attr("fspath")(data_dir).cast<std::string>();
  const granular::RunLimits limits = run_limits(max_memory, max_seconds, threads);
  packings::PackingModel model;
  granular::SceneRun run;
  nlohmann::ordered_json summary;
  const std::unique_ptr<granular::ProgressMeter> meter = progress_meter(progress, limits);
  {
    py::gil_scoped_release computing;
    model = packings::build_packing_model(scene, limits);
    run = packings::run_packing_scene(
        scene, model, run_options(delta_p, accuracy, estimate_error, limits, meter.get()));
    summary = packings::packing_summary(model, run);
  }
  if (meter) meter->finish();
  // the scene needs the moving geometry: a warning, as from the command line
  if (run.configuration_fails() &&
      PyErr_WarnEx(PyExc_UserWarning, run.configuration->describe().c_str(), 1) < 0)
    throw py::error_already_set();
  const granular::ImpactOutcome& impact = run.impact;
  PackingResult result;
  result.fill(run, summary);
  result.post_impact_velocities = per_body(impact.velocity_after, model.dimension);
  const int turning = model.dimension == 3 ? 3 : 1;
  result.post_impact_angular_velocities = impact.angular_velocity_after.size() > 0
                                              ? per_body(impact.angular_velocity_after, turning)
                                              : Eigen::MatrixXd::Zero(model.body_count(), turning);
  result.body_impulses =
      per_body((impact.velocity_after - model.velocity).cwiseProduct(model.mass), model.dimension);
  result.positions = model.position;
  result.radii = model.radius;
  result.contact_bodies.resize(model.contact_count(), 2);
  for (Eigen::Index c = 0; c < model.contact_count(); ++c) {
    const packings::PackingContact& contact = model.contacts[std::size_t(c)];
    result.contact_bodies.row(c) << int(contact.first), int(contact.second);
  }
  if (!summary["contacts_per_step"].is_null())
    result.contacts_per_step = summary["contacts_per_step"].get<double>();
  if (!run.frames.empty())
    result.frames = frames_dict(run.frames, model.body_count(), model.dimension);
  return result;
}

}  // namespace

void bind_packings(py::module_& module) {
  py::class_<PackingResult> packing_result(
      module, "PackingResult",
      "The outcome of run_packing(): a row per body, arrays per contact, the recorded series "
      "and frames, the whole summary.json");
  bind_scene_result(packing_result);
  packing_result
      .def_readonly("post_impact_velocities", &PackingResult::post_impact_velocities,
                    "m/s, bodies x dimension: the packing's beads (a lattice row by row), then "
                    "strikers")
      .def_readonly("post_impact_angular_velocities",
                    &PackingResult::post_impact_angular_velocities,
                    "rad/s, bodies x 1 (about z) in the plane, bodies x 3 in space, the bodies "
                    "in the same order; zeros when no contact rubs and no body spins")
      .def_readonly("body_impulses", &PackingResult::body_impulses, "N s, bodies x dimension")
      .def_readonly("positions", &PackingResult::positions, "m, the centres, bodies x dimension")
      .def_readonly("radii", &PackingResult::radii, "m, per body")
      .def_readonly("contact_bodies", &PackingResult::contact_bodies,
                    "contacts x 2: the bodies of each contact; -1 in the second for a wall")
      .def_readonly("contacts_per_step", &PackingResult::contacts_per_step,
                    "contacts integrated per step on average: the LZB integrators' work; None "
                    "for the compliant contacts (see the summary's moving_geometry)")
      .def_readonly("frames", &PackingResult::frames,
                    "None, or dict of 'time', 'forces' (frames x contacts), 'velocities' "
                    "(frames x bodies x dimension), and when the bodies turn "
                    "'angular_velocities' (frames x bodies x 1 in the plane, 3 in space)")
      .def("__repr__", [](const PackingResult& result) {
        return "<PackingResult " + result.status + ": " +
               std::to_string(result.post_impact_velocities.rows()) + " bodies, " +
               std::to_string(result.max_forces.size()) + " contacts>";
      });
  module.def("run_packing", &run_packing, py::arg("scene"), py::kw_only(),
             py::arg("delta_p") = py::none(), py::arg("accuracy") = py::none(),
             py::arg("estimate_error") = true, py::arg("data_dir") = py::none(),
             py::arg("max_memory") = granular::RunLimits{}.memory_gb,
             py::arg("max_seconds") = py::none(),
             py::arg("threads") = granular::RunLimits{}.threads, py::arg("progress") = false,
             "Runs a packing scene (a path, or a dict with its keys) as `mimpact packing` "
             "does; delta_p (N s) overrides the scene's impulse step; accuracy overrides its "
             "step rule and its accuracy; error_estimate as run_chain(); bead lists are read only "
             "inside data_dir (by default the scene file's directory, or the working directory "
             "for a dict); a run that would hold more than max_memory GB is refused before it "
             "starts, one past max_seconds s raises RuntimeError; threads as run_chain(); with "
             "progress=True a run longer "
             "than 2 s shows where it is on sys.stderr.");
}

}  // namespace mimpact::python
