#pragma once

#include <pybind11/pybind11.h>

#include <Eigen/Dense>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "json_conversion.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/granular/progress_meter.hpp"
#include "mimpact/granular/run_limits.hpp"
#include "mimpact/granular/scene_run.hpp"
#include "mimpact/granular/time_series.hpp"

// What the chain and packing bindings share: scenes given as a path or a dict, and time series
// as NumPy arrays.
namespace mimpact::python {

// A scene file's path (str or os.PathLike), read by load(path), or a dict with the keys of a
// scene file, read by read(document) with the same messages.
template <class Read, class Load>
auto load_scene_argument(const pybind11::object& scene, Read&& read, Load&& load) {
  namespace py = pybind11;
  if (py::isinstance<py::dict>(scene)) return read(nlohmann::json(to_json(scene, "scene")));
  if (py::isinstance<py::str>(scene) || py::hasattr(scene, "__fspath__"))
    return load(py::module_::import("os").attr("fspath")(scene).cast<std::string>());
  throw InvalidInput("scene = " + py::repr(scene).cast<std::string>() +
                     " is not allowed; allowed: a scene file's path or a dict with its keys");
}

// The limits of a run from Python's max_memory= (GB), max_seconds= (None: no limit) and threads=,
// checked.
granular::RunLimits run_limits(double max_memory, std::optional<double> max_seconds,
                               int threads = granular::RunLimits{}.threads);

// The progress line of progress=True, on sys.stderr in place (the GIL taken for each write, so
// that the run may release it); null for False.
std::unique_ptr<granular::ProgressMeter> progress_meter(bool progress,
                                                        const granular::RunLimits& limits);

// The options of a run from Python's delta_p=, accuracy= and estimate_error=, within `limits`,
// told to `meter` (or none).
granular::SceneRunOptions run_options(std::optional<double> delta_p, std::optional<double> accuracy,
                                      bool estimate_error, const granular::RunLimits& limits,
                                      granular::ProgressMeter* meter);

// [sample][column] as a samples x columns array
Eigen::MatrixXd table(const std::vector<std::vector<double>>& rows, std::size_t columns);

// {"time", "contacts", "forces" (samples x contacts), "bodies", "velocities" (samples x bodies,
// or samples x bodies x 2 in the plane)}
pybind11::dict series_dict(const granular::TimeSeries& series);

}  // namespace mimpact::python
