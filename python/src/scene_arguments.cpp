#include "scene_arguments.hpp"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

namespace py = pybind11;

namespace mimpact::python {

granular::RunLimits run_limits(double max_memory, std::optional<double> max_seconds, int threads) {
  granular::RunLimits limits{.memory_gb = max_memory, .memory_option = "max_memory="};
  if (max_seconds) limits.seconds = *max_seconds;
  limits.seconds_option = "max_seconds=";
  limits.threads = threads;
  limits.threads_option = "threads=";
  limits.check();
  return limits;
}

std::unique_ptr<granular::ProgressMeter> progress_meter(bool progress,
                                                        const granular::RunLimits& limits) {
  granular::ProgressMeter::Sink sink;
  if (progress)
    sink = [](const std::string& text) {
      py::gil_scoped_acquire python;
      try {
        const py::object stderr_stream = py::module_::import("sys").attr("stderr");
        stderr_stream.attr("write")(text);
        stderr_stream.attr("flush")();
      } catch (const py::error_already_set&) {  // a progress line is not worth the run
      }
    };
  return granular::run_meter(std::move(sink), limits.seconds, limits.seconds_option);
}

granular::SceneRunOptions run_options(std::optional<double> delta_p, std::optional<double> accuracy,
                                      bool estimate_error, const granular::RunLimits& limits,
                                      granular::ProgressMeter* meter) {
  granular::SceneRunOptions options;
  options.impact = {.delta_p = delta_p, .accuracy = accuracy};
  options.limits = limits;
  options.progress = meter;
  options.estimate_error = estimate_error;
  return options;
}

// [sample][column] as a samples x columns array
Eigen::MatrixXd table(const std::vector<std::vector<double>>& rows, std::size_t columns) {
  Eigen::MatrixXd matrix(Eigen::Index(rows.size()), Eigen::Index(columns));
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t c = 0; c < columns; ++c) matrix(Eigen::Index(r), Eigen::Index(c)) = rows[r][c];
  return matrix;
}

py::dict series_dict(const granular::TimeSeries& series) {
  py::dict dict;
  dict["time"] = Eigen::VectorXd(
      Eigen::Map<const Eigen::VectorXd>(series.time.data(), Eigen::Index(series.time.size())));
  dict["contacts"] = series.contacts;
  dict["forces"] = table(series.force, series.contacts.size());
  dict["bodies"] = series.bodies;
  const Eigen::MatrixXd velocities =
      table(series.velocity, series.bodies.size() * std::size_t(series.dimension));
  if (series.dimension == 1) {
    dict["velocities"] = velocities;
  } else {  // samples x bodies x components
    dict["velocities"] = py::module_::import("numpy")
                             .attr("asarray")(velocities)
                             .attr("reshape")(velocities.rows(), Eigen::Index(series.bodies.size()),
                                              series.dimension);
  }
  return dict;
}

}  // namespace mimpact::python
