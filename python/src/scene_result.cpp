#include "scene_result.hpp"

#include "json_conversion.hpp"
#include "mimpact/common/error.hpp"
#include "scene_arguments.hpp"

namespace mimpact::python {

void SceneResult::fill(const granular::SceneRun& run, const nlohmann::ordered_json& summary_json) {
  const granular::ImpactOutcome& impact = run.impact;
  if (!(impact.velocity_after.allFinite() && impact.result.max_force.allFinite()))
    throw Error("the run produced a non-finite velocity or force");
  impulses = impact.result.impulse;
  max_forces = impact.result.max_force;
  times_of_max_force = impact.result.time_of_max_force;
  status = summary_json["status"].get<std::string>();
  wall_time = impact.wall_time;
  duration = impact.result.duration;
  steps = impact.result.steps;
  delta_p = run.delta_p;
  if (run.recorded) series = series_dict(run.series);
  summary = from_json(summary_json);
}

}  // namespace mimpact::python
