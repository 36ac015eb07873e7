#pragma once

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Eigen/Dense>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "mimpact/granular/scene_run.hpp"

// What run_chain() and run_packing() return alike (the result of granular::run_scene): one
// struct, filled once and bound once; each geometry adds its own per-body arrays.
namespace mimpact::python {

struct SceneResult {
  Eigen::VectorXd impulses;            // N s, per contact
  Eigen::VectorXd max_forces;          // N, per contact
  Eigen::VectorXd times_of_max_force;  // s from the first impact, per contact
  std::string status;                  // "terminated", "step_limit" or "end_time"
  double wall_time = 0.0;              // s of computation
  double duration = 0.0;               // s, physical duration of the impacts
  std::int64_t steps = 0;
  std::optional<double> delta_p;  // N s, the impulse steps'; None for the other methods
  pybind11::object series = pybind11::none();  // dict of arrays when the scene records
  pybind11::dict summary;                      // everything summary.json holds

  // From the run and its summary.json; Error when a velocity or force is not finite.
  void fill(const granular::SceneRun& run, const nlohmann::ordered_json& summary_json);
};

// SceneResult's fields on the Python class of a result derived from it.
template <class Result>
void bind_scene_result(pybind11::class_<Result>& result) {
  result.def_readonly("impulses", &Result::impulses, "N s, per contact")
      .def_readonly("max_forces", &Result::max_forces, "N, the largest force per contact")
      .def_readonly("times_of_max_force", &Result::times_of_max_force,
                    "s from the first impact, when each contact's force peaked")
      .def_readonly("status", &Result::status,
                    "'terminated', 'step_limit' (LZB max_steps) or 'end_time' (compliant)")
      .def_readonly("wall_time", &Result::wall_time, "s of computation")
      .def_readonly("duration", &Result::duration, "s, physical duration of the impacts")
      .def_readonly("steps", &Result::steps, "impulse steps or integration steps")
      .def_readonly("delta_p", &Result::delta_p, "N s, the impulse steps'; None otherwise")
      .def_readonly("series", &Result::series,
                    "None, or when the scene records: dict of 'time' (s), 'contacts', 'forces' "
                    "(N, samples x contacts), 'bodies', 'velocities' (m/s, samples x bodies, "
                    "x dimension in a packing)")
      .def_readonly("summary", &Result::summary, "everything summary.json holds")
      .def_property_readonly(
          "error_estimate",
          [](const Result& self) { return self.summary.attr("get")("error_estimate"); },
          "None (estimate_error=False), or dict of 'rms' and 'worst' (the error of the "
          "velocities after the impact, of the fastest speed before it, RMS over the bodies and "
          "the worst body), 'method' and 'companion_seconds'")
      .def_property_readonly(
          "accuracy", [](const Result& self) { return self.summary.attr("get")("accuracy"); },
          "None, or when asked for an accuracy: dict of 'asked', 'met', 'runs', the step "
          "chosen ('tolerance' or 'delta_p') and 'ended' (None where met, else what ended the "
          "runs first)");
}

}  // namespace mimpact::python
