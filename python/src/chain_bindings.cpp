#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Eigen/Dense>
#include <optional>
#include <string>

#include "bindings.hpp"
#include "json_conversion.hpp"
#include "mimpact/chains/chain_convergence.hpp"
#include "mimpact/chains/chain_run.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/granular/hertz.hpp"
#include "mimpact/kernel/parameters.hpp"
#include "scene_arguments.hpp"
#include "scene_result.hpp"

namespace py = pybind11;

namespace mimpact::python {

namespace {

// What run_chain() returns: the arrays of summary.json, and the recorded time series.
struct ChainResult : SceneResult {
  Eigen::VectorXd post_impact_velocities;  // m/s, per body, strikers included
  py::dict energy;                         // the ledger (J): granular::EnergyLedger's fields
};

chains::ChainScene load_scene(const py::object& scene) {
  return load_scene_argument(
      scene,
      [](nlohmann::json document) {
        return chains::read_chain_scene(std::move(document), "scene");
      },
      [](const std::string& path) { return chains::load_chain_scene(path); });
}

// A scene file as a dict, checked as run_chain would check it.
py::object read_scene(const py::object& path_argument) {
  const std::string path =
      py::module_::import("os").attr("fspath")(path_argument).cast<std::string>();
  kernel::JsonDocument document =
      granular::parse_scene_document(granular::read_scene_file(path), path);
  chains::read_chain_scene(document.value, path, &document.locations);  // the file's messages
  return from_json(nlohmann::ordered_json(document.value));
}

// Parses and builds the scene without running it: the errors run_chain would raise first.
void check_scene(const py::object& scene) { chains::build_chain_model(load_scene(scene)); }

ChainResult run_chain(const py::object& scene_argument, std::optional<double> delta_p,
                      std::optional<double> accuracy, bool estimate_error, double max_memory,
                      std::optional<double> max_seconds, int threads, bool progress) {
  const chains::ChainScene scene = load_scene(scene_argument);
  const granular::RunLimits limits = run_limits(max_memory, max_seconds, threads);
  granular::SceneRun run;
  nlohmann::ordered_json summary;
  const std::unique_ptr<granular::ProgressMeter> meter = progress_meter(progress, limits);
  {
    py::gil_scoped_release computing;
    const chains::ChainModel model = chains::build_chain_model(scene, limits);
    run = chains::run_chain_scene(
        scene, model, run_options(delta_p, accuracy, estimate_error, limits, meter.get()));
    summary = chains::run_summary(model, run);
  }
  if (meter) meter->finish();
  ChainResult result;
  result.fill(run, summary);
  result.post_impact_velocities = run.impact.velocity_after;
  result.energy = py::dict(result.summary["energy"]);
  result.energy["dissipated"] =
      py::module_::import("numpy").attr("asarray")(result.energy["dissipated"]);
  return result;
}

py::object converge(const py::object& scene_argument, std::vector<double> tolerance,
                    std::optional<double> first, int rows, double max_memory) {
  const chains::ChainScene scene = load_scene(scene_argument);
  const granular::RunLimits limits = run_limits(max_memory, std::nullopt);
  nlohmann::ordered_json study;
  {
    py::gil_scoped_release computing;
    const chains::ChainModel model = chains::build_chain_model(scene, limits);
    study = chains::study_chain_convergence(scene, model,
                                            {.tolerance = std::move(tolerance),
                                             .first = first,
                                             .max_rows = rows,
                                             .tolerance_name = "tolerance",
                                             .first_name = "first",
                                             .rows_name = "rows",
                                             .limits = limits});
  }
  return from_json(study);
}

// {"density": kg/m^3, "young": Pa, "poisson": nu}, checked as a scene's "material"
granular::Material material(const py::dict& fields, const std::string& name) {
  return kernel::options_from<granular::Material>(kernel::Parameters(to_json(fields, name)),
                                                  {.name = name});
}

// A radius (m) checked as a scene's radii are.
double radius(double value, const std::string& name) {
  fields::Validator("", "").check(name, value, positive("m"));
  return value;
}

// The helpers' results are formulas of checked values, and can still leave double precision.
double finite_result(double value, const std::string& what) {
  if (!std::isfinite(value) || value == 0.0)
    throw InvalidInput(what + " = " + to_text(value) +
                       " leaves double precision; allowed: radii and moduli whose products stay "
                       "within it");
  return value;
}

// Hertz's bead mass and stiffnesses, for scenes built by hand.
void bind_hertz(py::module_& module) {
  module.def(
      "bead_mass",
      [](double r, const py::dict& of) {
        return finite_result(granular::bead_mass(radius(r, "radius"), material(of, "material")),
                             "bead_mass");
      },
      py::arg("radius"), py::arg("material"),
      "kg: (4/3) pi R^3 rho; material = {'density': kg/m^3, 'young': Pa, 'poisson': nu}");
  module.def(
      "hertz_stiffness",
      [](double radius_a, const py::dict& a, double radius_b, const py::dict& b) {
        return finite_result(
            granular::hertz_stiffness(radius(radius_a, "radius_a"), material(a, "material_a"),
                                      radius(radius_b, "radius_b"), material(b, "material_b")),
            "hertz_stiffness");
      },
      py::arg("radius_a"), py::arg("material_a"), py::arg("radius_b"), py::arg("material_b"),
      "N/m^1.5: K = (4/3) sqrt(R*) E* of two spheres (Johnson 1985, section 4.2)");
  module.def(
      "hertz_stiffness_wall",
      [](double r, const py::dict& bead, const py::dict& wall) {
        return finite_result(
            granular::hertz_stiffness_wall(radius(r, "radius"), material(bead, "bead"),
                                           material(wall, "wall")),
            "hertz_stiffness_wall");
      },
      py::arg("radius"), py::arg("bead"), py::arg("wall"),
      "N/m^1.5: the same for a sphere against a flat rigid wall (R* = R)");
}

// The outcome of run_chain(), pickled to cross processes.
void bind_chain_result(py::module_& module) {
  py::class_<ChainResult> chain_result(
      module, "ChainResult",
      "The outcome of run_chain(): arrays per body and per contact, the status, the recorded "
      "time series and the whole summary.json");
  bind_scene_result(chain_result);
  chain_result
      .def_readonly("post_impact_velocities", &ChainResult::post_impact_velocities,
                    "m/s, per body (strikers included), after the last impact")
      .def_readonly("energy", &ChainResult::energy,
                    "the energy ledger (J): kinetic_before, potential_before, work_of_forces, "
                    "kinetic_after, dissipated (per contact), dissipated_total, potential_left; "
                    "before + potential_before + work_of_forces = after + dissipated_total + "
                    "potential_left to round-off")
      .def("__repr__",
           [](const ChainResult& result) {
             return "<ChainResult " + result.status + ": " +
                    std::to_string(result.post_impact_velocities.size()) + " bodies, " +
                    std::to_string(result.impulses.size()) + " contacts, " +
                    std::to_string(result.steps) + " steps>";
           })
      // pickled to cross processes: a sweep's results come back from Dask's workers
      .def(py::pickle(
          [](const ChainResult& r) {
            return py::make_tuple(r.post_impact_velocities, r.impulses, r.max_forces,
                                  r.times_of_max_force, r.status, r.wall_time, r.duration, r.steps,
                                  r.delta_p, r.energy, r.series, r.summary);
          },
          [](const py::tuple& state) {
            if (state.size() != 12) throw InvalidInput("a ChainResult pickled by another version");
            ChainResult r;
            r.post_impact_velocities = state[0].cast<Eigen::VectorXd>();
            r.impulses = state[1].cast<Eigen::VectorXd>();
            r.max_forces = state[2].cast<Eigen::VectorXd>();
            r.times_of_max_force = state[3].cast<Eigen::VectorXd>();
            r.status = state[4].cast<std::string>();
            r.wall_time = state[5].cast<double>();
            r.duration = state[6].cast<double>();
            r.steps = state[7].cast<std::int64_t>();
            r.delta_p = state[8].cast<std::optional<double>>();
            r.energy = state[9].cast<py::dict>();
            r.series = state[10];
            r.summary = state[11].cast<py::dict>();
            return r;
          }));
}

// The runs of a chain scene: run, read, check, converge.
void bind_chain_runs(py::module_& module) {
  module.def(
      "run_chain", &run_chain, py::arg("scene"), py::kw_only(), py::arg("delta_p") = py::none(),
      py::arg("accuracy") = py::none(), py::arg("estimate_error") = true,
      py::arg("max_memory") = granular::RunLimits{}.memory_gb, py::arg("max_seconds") = py::none(),
      py::arg("threads") = granular::RunLimits{}.threads, py::arg("progress") = false,
      "The impacts of a chain scene (a scene file's path or a dict with its keys), by "
      "the method it chooses; delta_p (N s) overrides the scene's impulse step; accuracy "
      "(a share of the fastest speed before the impact) overrides its step rule and its "
      "accuracy: the run chooses its step to meet it; the result's error_estimate comes "
      "from a companion run at another step, unless estimate_error=False; a run "
      "that would hold more than max_memory GB is refused before it starts, one that "
      "takes more than max_seconds s of wall-clock time raises RuntimeError; threads=2 (the "
      "default) runs the estimate's companion beside the run, threads=1 after it; with "
      "progress=True a run longer than 2 s shows where it is on sys.stderr.");
  module.def("read_scene", &read_scene, py::arg("path"),
             "a scene file (JSON, // comments allowed) as a dict, checked like run_chain()'s");
  module.def("check_scene", &check_scene, py::arg("scene"),
             "raises the ValueError run_chain(scene) would raise for bad input, without running");
  module.def("converge", &converge, py::arg("scene"), py::kw_only(),
             py::arg("tolerance") = std::vector<double>{}, py::arg("first") = py::none(),
             py::arg("rows") = 12, py::arg("max_memory") = granular::RunLimits{}.memory_gb,
             "The convergence study of `mimpact converge`: the adaptive integrator's tolerance "
             "t, t/10, ... or delta_p h, h/2, ... until the post-impact velocities (and peak "
             "forces) change by at most tolerance = [eps+, eps]; returns its rows as a dict.");
}

}  // namespace

void bind_chains(py::module_& module) {
  bind_hertz(module);
  bind_chain_result(module);
  bind_chain_runs(module);
}

}  // namespace mimpact::python
