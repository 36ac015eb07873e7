#include "mimpact/packings/packing_run.hpp"

#include <cmath>
#include <cstdio>
#include <numeric>

#include "mimpact/common/error.hpp"
#include "mimpact/granular/energy_ledger.hpp"
#include "mimpact/granular/impact_recorder.hpp"

namespace mimpact::packings {

namespace {

void check_record(const PackingScene& scene, const PackingModel& model) {
  auto check = [&](const std::vector<int>& indices, const std::string& key, Eigen::Index count,
                   const std::string& what) {
    for (std::size_t k = 0; k < indices.size(); ++k)
      if (indices[k] >= count)
        throw InvalidInput(
            invalid_value_message("record." + key + "[" + std::to_string(k) + "]", indices[k],
                                  "a " + what + " index in [0, " + std::to_string(count) + ")"));
  };
  check(scene.record.contacts, "contacts", model.contact_count(), "contact");
  check(scene.record.beads, "beads", model.body_count(), "body (beads, then strikers)");
}

std::vector<double> components(const Vector& v) { return {v.data(), v.data() + v.size()}; }

// "[a, b]" (or "[a, b, c]"), each component printed with `format`
std::string bracketed(const Vector& v, const char* format) {
  std::string text = "[";
  char number[32];
  for (Eigen::Index k = 0; k < v.size(); ++k) {
    std::snprintf(number, sizeof number, format, v(k));
    if (k > 0) text += ", ";
    text += number;
  }
  return text + "]";
}

// "x,y" (or "x,y,z") with `prefix` before each: a CSV header's coordinates
std::string axis_names(const std::string& prefix, int dimension) {
  static const char* const kAxes[] = {"x", "y", "z"};
  std::string text;
  for (int k = 0; k < dimension; ++k) {
    if (k > 0) text += ",";
    text += prefix;
    text += kAxes[k];
  }
  return text;
}

// ",cell" at the end of a CSV line
void add_cell(std::string& line, const std::string& cell) {
  line += ',';
  line += cell;
}

// %.17g: every double read back to the bit
std::string full_precision(double value) {
  char number[32];
  std::snprintf(number, sizeof number, "%.17g", value);
  return number;
}

// [[vx, vy], ...] per body
nlohmann::ordered_json per_body(const PackingModel& model, const Eigen::VectorXd& values) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (Eigen::Index b = 0; b < model.body_count(); ++b)
    list.push_back(components(model.of(values, b)));
  return list;
}

// About the origin: before, with the bodies where the first impact found them; after, where the
// run left them if it moved them (packing_model.hpp).
nlohmann::ordered_json angular_momentum_json(const PackingModel& model,
                                             const granular::ImpactOutcome& impact) {
  const Eigen::VectorXd before =
      model.rotation ? model.rotation->angular_velocity : Eigen::VectorXd();
  const double t = impact.impact_time;
  return {{"before", components(angular_momentum(model, model.velocity, before, t))},
          {"after",
           components(angular_momentum(model, impact.velocity_after, impact.angular_velocity_after,
                                       t, impact.position_after))}};
}

double contacts_per_step(const granular::ImpactOutcome& impact) {
  return impact.result.steps > 0 ? double(impact.result.contact_steps) / double(impact.result.steps)
                                 : 0.0;
}

// The work of a step as the console tells it: the bodies a group's step carries in the moving
// geometry, the contacts updated by the LZB integrators, nothing where neither is counted (the
// frozen compliant contacts)
std::string step_work(const granular::ImpactOutcome& impact,
                      const granular::MovingContactsStats& moving) {
  char text[64];
  if (moving.steps > 0)
    std::snprintf(text, sizeof text, ", %.1f bodies per step",
                  double(moving.member_steps) / double(moving.steps));
  else if (impact.result.contact_steps > 0)
    std::snprintf(text, sizeof text, ", %.1f contacts per step", contacts_per_step(impact));
  else
    text[0] = '\0';
  return text;
}

// the contacts the impact reached: those that carried a force
Eigen::Index contacts_reached(const granular::ImpactOutcome& impact) {
  return Eigen::Index((impact.result.max_force.array() > 0.0).count());
}

// per body: its angular velocity, a number (about z) in the plane, [wx, wy, wz] in space; 0
// for bodies that do not turn
nlohmann::ordered_json per_body_turning(const PackingModel& model,
                                        const Eigen::VectorXd& angular_velocity) {
  const int count = model.dimension == 3 ? 3 : 1;
  const Eigen::VectorXd turning = angular_velocity.size() > 0
                                      ? angular_velocity
                                      : Eigen::VectorXd::Zero(count * model.body_count());
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (Eigen::Index b = 0; b < model.body_count(); ++b)
    if (count == 1)
      list.push_back(turning(b));
    else
      list.push_back(components(Vector(turning.segment(3 * b, 3))));
  return list;
}

nlohmann::ordered_json configuration_json(
    const std::optional<granular::ConfigurationCheck>& check) {
  if (!check) return nullptr;
  if (!check->not_made.empty())
    return {{"holds", false}, {"not_made", check->not_made}, {"time", check->time}};
  return {{"time", check->time},
          {"tolerance", check->tolerance},
          {"accuracy", check->accuracy},
          {"rms_error", check->rms_error},
          {"worst_error", check->worst_error},
          {"worst_body", check->worst_body},
          {"holds", check->holds()},
          {"wall_time", check->wall_time}};
}

// The work of a compliant run in the moving geometry (docs/design/moving_geometry.md), or null.
nlohmann::ordered_json moving_json(const granular::MovingContactsStats& work) {
  if (work.windows == 0) return nullptr;
  nlohmann::ordered_json json = {{"body_steps", work.member_steps},
                                 {"group_steps", work.steps},
                                 {"windows", work.windows},
                                 {"group_restarts", work.group_restarts},
                                 {"body_restarts", work.member_restarts},
                                 {"groups_integrated_again", work.redone_groups},
                                 {"largest_group", work.largest_group},
                                 {"most_bodies_in_motion", work.most_bodies_in_motion},
                                 {"contacts_loaded", work.contacts_loaded}};
  if (work.amended_springs > 0) json["springs_amended_at_a_switch"] = work.amended_springs;
  return json;
}

granular::TimeSeries frame_table(const granular::Frames& frames, bool forces, int dimension) {
  granular::TimeSeries table;
  table.time = frames.time;
  table.dimension = dimension;
  const std::vector<std::vector<double>>& rows = forces ? frames.force : frames.velocity;
  const std::size_t columns = rows.empty() ? 0 : rows.front().size();
  std::vector<int>& labels = forces ? table.contacts : table.bodies;
  labels.resize(forces ? columns : columns / std::size_t(dimension));
  std::iota(labels.begin(), labels.end(), 0);
  (forces ? table.force : table.velocity) = rows;
  return table;
}

}  // namespace

granular::SceneRun run_packing_scene(const PackingScene& scene, const PackingModel& model,
                                     const granular::SceneRunOptions& options) {
  check_record(scene, model);
  return granular::run_scene(
      model, [&] { return build_packing_system(model); },
      {.impact = scene.impact,
       .method = scene.method,
       .compliant = scene.compliant,
       .record = scene.run_record(),
       .frame_every = scene.record.frames,
       .source = scene.source,
       .configuration_check = &scene.configuration_check,
       .accuracy = scene.accuracy},
      options);
}

nlohmann::ordered_json packing_summary(const PackingModel& model, const granular::SceneRun& run) {
  using json = nlohmann::ordered_json;
  const granular::ImpactOutcome& impact = run.impact;
  json contacts = json::array();
  for (Eigen::Index c = 0; c < model.contact_count(); ++c) {
    const PackingContact& contact = model.contacts[std::size_t(c)];
    json entry{{"index", c}, {"first", contact.first}};
    if (contact.second >= 0)
      entry["second"] = contact.second;
    else
      entry["wall"] = contact.wall;
    entry["normal"] = components(contact.normal);
    entry["max_force"] = impact.result.max_force(c);
    entry["time_of_max"] = impact.result.time_of_max_force(c);
    entry["impulse"] = impact.result.impulse(c);
    if (model.rotation && model.rotation->tangential.rows_of(c) > 0) {
      const Eigen::Index first = model.rotation->tangential.first_row[std::size_t(c)];
      const int rows = model.rotation->tangential.rows_of(c);
      entry["tangential_impulse"] =
          components(Vector(impact.result.tangential_impulse.segment(first, rows)));
      entry["slip_after"] = components(Vector(impact.result.slip.segment(first, rows)));
    }
    contacts.push_back(entry);
  }
  const Eigen::VectorXd& after = impact.velocity_after;
  const Eigen::VectorXd body_impulses = (after - model.velocity).cwiseProduct(model.mass);
  json summary{
      {"status", impact.cut_by_end_time ? "end_time" : numerics::to_string(impact.result.status)},
      {"method", enum_name(run.method)},
      {"method_choice", run.why.empty() ? json(nullptr) : json(run.why)},
      {"integrator", run.method == granular::Method::compliant
                         ? json(nullptr)
                         : json(enum_name(run.options.chosen_integrator()))},
      {"delta_p", run.delta_p ? json(*run.delta_p) : json(nullptr)},
      {"relative_delta_p",
       run.options.relative_delta_p ? json(*run.options.relative_delta_p) : json(nullptr)},
      {"tolerance", run.method == granular::Method::compliant ? json(run.compliant.tolerance)
                    : run.options.chosen_integrator() == plugins::LzbIntegrator::adaptive
                        ? json(run.options.adaptive_tolerance())
                        : json(nullptr)},
      {"beads", model.bead_count},
      {"bodies", model.body_count()},
      {"post_impact_velocities", per_body(model, after)},
      {"post_impact_angular_velocities", per_body_turning(model, impact.angular_velocity_after)},
      {"body_impulses", per_body(model, body_impulses)},
      {"steps", impact.result.steps},
      // the LZB integrators' work; the compliant contacts' is moving_geometry's
      {"contacts_per_step",
       run.method == granular::Method::lzb ? json(contacts_per_step(impact)) : json(nullptr)},
      {"contacts_reached", contacts_reached(impact)},
      {"impacts", impact.impact_times.size()},
      {"impact_time", impact.impact_time},
      {"impact_duration", impact.result.duration},
      {"kinetic_energy",
       {{"before", granular::kinetic_energy(model, model.velocity)},
        {"after", granular::kinetic_energy(model, after)},
        {"residual_potential", impact.result.residual_energy}}},
      {"momentum",
       {{"before", components(momentum(model, model.velocity))},
        {"after", components(momentum(model, after))}}},
      {"angular_momentum", angular_momentum_json(model, impact)},
      {"energy", granular::ledger_json(granular::energy_ledger(model, impact))},
      {"wall_time", impact.wall_time},
      {"configuration_check", configuration_json(run.configuration)},
      {"moving_geometry", moving_json(run.moving)},
      {"contacts", contacts}};
  if (run.error_estimate)
    summary["error_estimate"] = granular::error_estimate_json(run.error_estimate);
  if (run.accuracy) summary["accuracy"] = granular::accuracy_json(*run.accuracy);
  return summary;
}

std::string packing_report(const PackingModel& model, const granular::SceneRun& run) {
  const granular::ImpactOutcome& impact = run.impact;
  const double before = granular::kinetic_energy(model, model.velocity);
  const double after = granular::kinetic_energy(model, impact.velocity_after);
  Eigen::Index fastest = 0;
  double top = 0.0;
  for (Eigen::Index b = 0; b < model.body_count(); ++b)
    if (model.of(impact.velocity_after, b).norm() > top) {
      top = model.of(impact.velocity_after, b).norm();
      fastest = b;
    }
  char text[1024];
  std::snprintf(
      text, sizeof text,
      "%lld beads, %lld strikers, %lld contacts, %s\n"
      "%lld steps%s, %lld contacts reached, in %.3g s of computation; "
      "the impact lasts %.6g s (%s)\n"
      "kinetic energy %.6g J -> %.6g J (%+.4f %%); momentum %s -> %s N s\n"
      "fastest body after the impact: %lld, %s m/s (all in summary.json)\n",
      (long long)model.bead_count, (long long)(model.body_count() - model.bead_count),
      (long long)model.contact_count(), granular::describe_method(run).c_str(),
      (long long)impact.result.steps, step_work(impact, run.moving).c_str(),
      (long long)contacts_reached(impact), impact.wall_time, impact.result.duration,
      impact.cut_by_end_time ? "cut by compliant.end_time with contacts still closed"
                             : std::string(numerics::to_string(impact.result.status)).c_str(),
      before, after, 100.0 * (after / before - 1.0),
      bracketed(momentum(model, model.velocity), "%.9g").c_str(),
      bracketed(momentum(model, impact.velocity_after), "%.9g").c_str(), (long long)fastest,
      bracketed(model.of(impact.velocity_after, fastest), "%.6g").c_str());
  std::string report = text;
  if (model.rotation) {  // the bodies turn: their energy, the slip's and the angular momentum
    const granular::EnergyLedger ledger = granular::energy_ledger(model, impact);
    const double t = impact.impact_time;
    std::snprintf(
        text, sizeof text,
        "rotational energy %.6g J -> %.6g J, slip took %.6g J; angular momentum %s -> %s N m s\n",
        ledger.rotational_before, ledger.rotational_after, ledger.slip.sum(),
        bracketed(angular_momentum(model, model.velocity, model.rotation->angular_velocity, t),
                  "%.9g")
            .c_str(),
        bracketed(angular_momentum(model, impact.velocity_after, impact.angular_velocity_after, t,
                                   impact.position_after),
                  "%.9g")
            .c_str());
    report += text;
  }
  report += granular::describe_error(run);
  if (run.configuration && run.configuration->holds())  // else a warning (packing_command.cpp)
    return report + run.configuration->describe() + "\n";
  return report;
}

std::string bodies_csv(const PackingModel& model) {
  const int d = model.dimension;
  std::string text = "body";
  add_cell(text, axis_names("", d));
  text += ",radius,mass\n";
  for (Eigen::Index b = 0; b < model.body_count(); ++b) {
    text += std::to_string(b);
    for (int k = 0; k < d; ++k) add_cell(text, full_precision(model.position(b, k)));
    add_cell(text, full_precision(model.radius(b)));
    add_cell(text, full_precision(model.mass(d * b)));
    text += '\n';
  }
  return text;
}

std::string contacts_csv(const PackingModel& model) {
  const int d = model.dimension;
  std::string text = "contact,first,second,wall";
  add_cell(text, axis_names("n", d));
  add_cell(text, axis_names("", d));
  text += '\n';
  for (std::size_t c = 0; c < model.contacts.size(); ++c) {
    const PackingContact& contact = model.contacts[c];
    // where it touches: the first body's surface along the normal (against a wall, its
    // surface towards the wall)
    const Vector centre = model.position.row(contact.first).transpose();
    const double side = contact.second >= 0 ? 1.0 : -1.0;
    const Vector at = centre + side * model.radius(contact.first) * contact.normal;
    text += std::to_string(c);
    add_cell(text, std::to_string(contact.first));
    add_cell(text, std::to_string(contact.second));
    add_cell(text, std::to_string(contact.wall));
    for (int k = 0; k < d; ++k) add_cell(text, full_precision(contact.normal(k)));
    for (int k = 0; k < d; ++k) add_cell(text, full_precision(at(k)));
    text += '\n';
  }
  return text;
}

std::string frame_forces_csv(const granular::Frames& frames) {
  return frame_table(frames, true, 1).forces_csv();
}

std::string frame_velocities_csv(const granular::Frames& frames, int dimension) {
  return frame_table(frames, false, dimension).velocities_csv();
}

std::string frame_angular_velocities_csv(const granular::Frames& frames, int dimension) {
  const int components = dimension == 3 ? 3 : 1;
  const std::size_t columns =
      frames.angular_velocity.empty() ? 0 : frames.angular_velocity.front().size();
  std::vector<int> bodies(columns / std::size_t(components));
  std::iota(bodies.begin(), bodies.end(), 0);
  return granular::vector_csv(frames.time, frames.angular_velocity, bodies, components,
                              components == 1 ? "wz" : "w");
}

std::string frame_positions_csv(const granular::Frames& frames, int dimension) {
  const std::size_t columns = frames.position.empty() ? 0 : frames.position.front().size();
  std::vector<int> bodies(columns / std::size_t(dimension));
  std::iota(bodies.begin(), bodies.end(), 0);
  return granular::vector_csv(frames.time, frames.position, bodies, dimension, "");
}

}  // namespace mimpact::packings
