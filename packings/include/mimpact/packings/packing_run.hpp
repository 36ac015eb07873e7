#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "mimpact/granular/impact_outcome.hpp"
#include "mimpact/granular/run_limits.hpp"
#include "mimpact/granular/scene_run.hpp"
#include "mimpact/granular/time_series.hpp"
#include "mimpact/packings/packing_model.hpp"
#include "mimpact/packings/packing_scene.hpp"

// One run of a packing scene by the method it chooses (granular::run_scene on the packing's
// model and system): what `mimpact packing` and the Python module's run_packing() share.
namespace mimpact::packings {

// The LZB impacts (impulse steps at delta_p, or the adaptive integrator) through the
// event-driven scheme, or the compliant contacts integrated in time, as the scene says. Throws
// InvalidInput for a missing or out-of-range delta_p, a delta_p given to another method, and
// recorded contacts or beads out of range.
granular::SceneRun run_packing_scene(const PackingScene& scene, const PackingModel& model,
                                     const granular::SceneRunOptions& options = {});

// summary.json of `mimpact packing`: status, method, post-impact velocities [vx, vy] per body
// (the packing's beads, then the strikers) and the impulse each body received, per contact its
// bodies, peak force, time and impulse, steps and the contacts integrated per step (the work),
// kinetic energy, vector momentum and the energy ledger.
nlohmann::ordered_json packing_summary(const PackingModel& model, const granular::SceneRun& run);

// A few lines for people: sizes, method, steps and contacts per step, energy and momentum, the
// fastest bodies after the impact, and an LZB run's configuration check when it holds (when it
// does not, the caller warns with ConfigurationCheck::describe()).
std::string packing_report(const PackingModel& model, const granular::SceneRun& run);

// The geometry for viewers and plots: "body,x,y,radius,mass" per body, and
// "contact,first,second,wall,nx,ny,x,y" per contact (second -1 for a wall, whose index is
// `wall`; x, y where the contact touches).
std::string bodies_csv(const PackingModel& model);
std::string contacts_csv(const PackingModel& model);
// Frames as two tables: "time,F_0,...,F_m-1" and "time,vx_0,vy_0,..." (with vz_0 in space),
// one row per frame.
std::string frame_forces_csv(const granular::Frames& frames);
std::string frame_velocities_csv(const granular::Frames& frames, int dimension);
// The frames' angular velocities when the bodies turn: "time,wz_0,wz_1,..." in the plane,
// "time,wx_0,wy_0,wz_0,..." in space (rad/s).
std::string frame_angular_velocities_csv(const granular::Frames& frames, int dimension);
// The frames' positions, "time,x_0,y_0,...", in the moving geometry (frames.position).
std::string frame_positions_csv(const granular::Frames& frames, int dimension);

}  // namespace mimpact::packings
