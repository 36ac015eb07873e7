#include "mimpact/granular/impact_runs.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "compliant_engine.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/granular/impact_recorder.hpp"
#include "mimpact/kernel/simulation.hpp"
#include "mimpact/plugins/acceleration_lcp_problem.hpp"
#include "mimpact/plugins/event_driven_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"

namespace mimpact::granular {

namespace {

// Keeps every impact of the run and ends it with the impact of the last striker to arrive.
class Impacts : public kernel::SimulationObserver {
 public:
  Impacts(const ContactModel& model, double last_arrival)
      : model_(model), last_arrival_(last_arrival) {
    const Eigen::Index m = model.contact_count();
    total_.impulse = Eigen::VectorXd::Zero(m);
    total_.max_force = Eigen::VectorXd::Zero(m);
    total_.time_of_max_force = Eigen::VectorXd::Zero(m);
    total_.work = Eigen::VectorXd::Zero(m);
    total_.stored_energy = Eigen::VectorXd::Zero(m);
  }

  kernel::EventStatus on_step(const kernel::Simulation&, const kernel::StepReport& step) override {
    if (!step.impact) return kernel::EventStatus::proceed();
    add(*step.impact);
    return step.impact->time >= last_arrival_ - 1e-9
               ? kernel::EventStatus::terminate("the last striker has struck")
               : kernel::EventStatus::proceed();
  }

  ImpactOutcome result() {
    if (result_.impact_times.empty())
      throw Error("the strikers never reached their targets within the simulated time");
    split_velocities(model_, generalized_after_, result_.velocity_after,
                     result_.angular_velocity_after);
    total_.velocity = model_.W.transpose() * result_.velocity_after;
    if (model_.rotation) total_.slip = slip(*model_.rotation);
    result_.result = total_;
    return result_;
  }

 private:
  void add(const kernel::ImpactReport& report) {
    const numerics::ImpactResult& impact = report.result;
    // A step the LZB thresholds cannot resolve the approach with would let the striker through.
    if (impact.steps == 0)
      throw InvalidInput(
          "the impact at t = " + to_text(report.time) +
          " s took no impulse step: no contact approaches faster than the LZB velocity "
          "threshold (0.1 H_jj delta_p, or impact.fixed_thresholds.velocity); take a "
          "smaller delta_p or threshold");
    if (result_.impact_times.empty()) result_.impact_time = report.time;
    const double offset = report.time - result_.impact_time;
    for (std::size_t k = 0; k < report.interactions.size(); ++k) {
      const kernel::Index j = report.interactions[k];
      const auto i = Eigen::Index(k);
      total_.impulse(j) += impact.impulse(i);
      total_.work(j) += impact.work(i);
      total_.stored_energy(j) += impact.stored_energy(i);
      if (impact.max_force(i) > total_.max_force(j)) {
        total_.max_force(j) = impact.max_force(i);
        total_.time_of_max_force(j) = offset + impact.time_of_max_force(i);
      }
    }
    if (model_.rotation) add_tangential(report);
    total_.steps += impact.steps;
    total_.contact_steps += impact.contact_steps;
    total_.residual_energy += impact.residual_energy;
    total_.duration = offset + impact.duration;
    result_.wall_time += report.wall_time;
    result_.impact_times.push_back(report.time);
    Eigen::VectorXd before, angular_before;
    split_velocities(model_, report.generalized_velocity_before, before, angular_before);
    result_.velocities_before.push_back(std::move(before));
    if (model_.rotation) result_.angular_velocities_before.push_back(std::move(angular_before));
    generalized_after_ = report.generalized_velocity_after;
  }

  // The tangential impulses of the impact's rows (its contacts' rows, in its order) added to
  // the model's rows, and its slip work to its contacts'.
  void add_tangential(const kernel::ImpactReport& report) {
    const numerics::TangentialRows& rows = model_.rotation->tangential;
    if (total_.tangential_impulse.size() == 0) {
      total_.tangential_impulse = Eigen::VectorXd::Zero(rows.rows());
      total_.slip_work = Eigen::VectorXd::Zero(model_.contact_count());
    }
    const numerics::ImpactResult& impact = report.result;
    if (impact.tangential_impulse.size() == 0) return;
    Eigen::Index local = 0;
    for (std::size_t k = 0; k < report.interactions.size(); ++k) {
      const auto j = Eigen::Index(report.interactions[k]);
      const Eigen::Index first = rows.first_row[std::size_t(j)];
      for (int r = 0; r < rows.rows_of(j); ++r)
        total_.tangential_impulse(first + r) += impact.tangential_impulse(local++);
      total_.slip_work(j) += impact.slip_work(Eigen::Index(k));
    }
  }

  // every row's slip after the last impact, from the bodies' velocities
  Eigen::VectorXd slip(const Rotation& rotation) const {
    return rotation.W_t.transpose() * result_.velocity_after +
           rotation.R_t.transpose() * result_.angular_velocity_after;
  }

  const ContactModel& model_;
  double last_arrival_;
  Eigen::VectorXd generalized_after_;
  numerics::ImpactResult total_;
  ImpactOutcome result_;
};

// What one sample and one frame of a compliant run keep (bytes), as ImpactRecorder counts them.
RecordingBudget compliant_budget(const ContactModel& model, const RecordSpec& record,
                                 int frame_every, const RunLimits& limits) {
  const double columns =
      double(record.contacts.size() + record.bodies.size() * std::size_t(model.dimension) + 1);
  const double all = double(model.contact_count() + model.mass.size());
  return RecordingBudget(150.0 + 60.0 * columns, 60.0 * all, limits,
                         sampling_fields(record, true, frame_every));
}

// The event-driven motion's tolerances at the scene's scales: a contact is closed within the
// penetration tolerance of its gap (a share of the radii: a lattice of radius 1e6 m has gaps of
// 1e-9 m by rounding), and impacts when it approaches faster than 1e-9 of the fastest approach.
plugins::EventDrivenOptions event_options(const ContactModel& model) {
  plugins::EventDrivenOptions options;
  options.gap_tolerance = simulation_options(model).penetration_tolerance;
  options.velocity_tolerance = 1e-9 * model.u_minus.cwiseAbs().maxCoeff();
  return options;
}

}  // namespace

ImpactOutcome simulate_impacts(const ContactModel& model,
                               std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                               const plugins::LzbImpactOptions& options,
                               numerics::ImpactObserver* observer) {
  auto impacts = std::make_unique<plugins::LzbImpactProblem>(options);
  impacts->set_impact_observer(observer);
  kernel::Simulation simulation(
      std::move(system), std::make_unique<plugins::EventDrivenIntegrator>(event_options(model)),
      {.impacts = std::move(impacts),
       .contact_forces = std::make_unique<plugins::AccelerationLcpProblem>()},
      simulation_options(model));
  const double last_arrival =
      *std::max_element(model.striker_arrivals.begin(), model.striker_arrivals.end());
  Impacts all(model, last_arrival);
  simulation.add_observer(all);
  simulation.run(0.0, 2.0 * last_arrival + 1.0);
  return all.result();
}

ImpactOutcome simulate_impact_numerics(const ContactModel& model,
                                       const numerics::LzbOptions& options,
                                       numerics::ImpactObserver* observer) {
  numerics::LzbImpulseIntegrator integrator(options);
  ImpactOutcome impact;
  const auto start = std::chrono::steady_clock::now();
  impact.result = model.rotation
                      ? integrator.integrate(model.H, model.u_minus, model.laws,
                                             model.rotation->tangential, observer)
                      : integrator.integrate(model.H, model.u_minus, model.laws, observer);
  impact.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  impact.velocity_after =
      model.velocity + (model.W * impact.result.impulse).cwiseQuotient(model.mass);
  if (model.rotation) {  // + M^-1 W_t P_t, and omega+ = omega- + I^-1 R_t P_t
    const Rotation& rotation = *model.rotation;
    const Eigen::VectorXd& tangential = impact.result.tangential_impulse;
    impact.velocity_after += (rotation.W_t * tangential).cwiseQuotient(model.mass);
    impact.angular_velocity_after = turned(rotation, rotation.angular_velocity, tangential);
  }
  impact.impact_times = {0.0};
  impact.velocities_before = {model.velocity};
  if (model.rotation) impact.angular_velocities_before = {model.rotation->angular_velocity};
  return impact;
}

namespace {

// What a compliant run samples, until when, and the memory its samples may take.
struct Sampling {
  const RecordSpec& record;
  int frame_every;
  double end;  // s
  RecordingBudget budget;
};

// The one recorder loop of a compliant run, whichever engine: a sample of the recorded contacts
// and bodies every record.interval from t = 0 (and where the engine stopped), every
// frame_every-th sample a frame of the whole scene, until `end` or the contacts are done. Times
// on the run's clock.
void record(CompliantEngine& engine, const ContactModel& model, Sampling sampling,
            CompliantRun& run) {
  const RecordSpec& record = sampling.record;
  const int frame_every = sampling.frame_every;
  const double end = sampling.end;
  const int d = model.dimension;
  for (std::int64_t k = 0;; ++k) {
    const double t = std::min(end, double(k) * record.interval);
    engine.advance_to(t);
    run.series.time.push_back(engine.time());
    std::vector<double> forces, velocities;
    for (int c : record.contacts) forces.push_back(engine.force(c));
    for (int b : record.bodies)
      for (int i = 0; i < d; ++i) velocities.push_back(engine.velocity(b)(i));
    run.series.force.push_back(std::move(forces));
    run.series.velocity.push_back(std::move(velocities));
    const bool frame = frame_every > 0 && k % frame_every == 0;
    sampling.budget.add(frame);
    if (frame) {
      run.frames.time.push_back(engine.time());
      std::vector<double> all_forces, all_velocities, all_positions;
      for (Eigen::Index c = 0; c < model.contact_count(); ++c)
        all_forces.push_back(engine.force(c));
      for (Eigen::Index b = 0; b < model.body_count(); ++b)
        for (int i = 0; i < d; ++i) {
          all_velocities.push_back(engine.velocity(b)(i));
          if (engine.has_positions()) all_positions.push_back(engine.position(b)(i));
        }
      run.frames.force.push_back(std::move(all_forces));
      run.frames.velocity.push_back(std::move(all_velocities));
      if (model.rotation) {
        std::vector<double> spins;
        for (Eigen::Index b = 0; b < model.body_count(); ++b)
          for (int i = 0; i < model.rotation->components; ++i)
            spins.push_back(engine.angular_velocity(b)(i));
        run.frames.angular_velocity.push_back(std::move(spins));
      }
      if (engine.has_positions()) run.frames.position.push_back(std::move(all_positions));
    }
    if (t >= end || engine.ended()) break;
  }
}

// A compliant run's outcome where the bodies turn: their spins after, the tangential impulses
// and slip work of the rubbing contacts, and every row's slip after.
void add_rotation(const CompliantEngine& engine, const ContactModel& model, ImpactOutcome& impact) {
  const Rotation& rotation = *model.rotation;
  const int r = rotation.components;
  impact.angular_velocity_after.resize(r * model.body_count());
  for (Eigen::Index b = 0; b < model.body_count(); ++b)
    impact.angular_velocity_after.segment(r * b, r) = engine.angular_velocity(b).head(r);
  numerics::ImpactResult& result = impact.result;
  const numerics::TangentialRows& rows = rotation.tangential;
  result.tangential_impulse = Eigen::VectorXd::Zero(rows.rows());
  result.slip_work = Eigen::VectorXd::Zero(model.contact_count());
  for (Eigen::Index c = 0; c < model.contact_count(); ++c) {
    const ContactTotals totals = engine.totals(c);
    result.tangential_impulse.segment(rows.first_row[std::size_t(c)], rows.rows_of(c)) =
        totals.tangential_impulse.head(rows.rows_of(c));
    result.slip_work(c) = totals.slip_work;
  }
  result.slip = rotation.W_t.transpose() * impact.velocity_after +
                rotation.R_t.transpose() * impact.angular_velocity_after;
  impact.angular_velocities_before = {rotation.angular_velocity};
}

// The one assembly of a compliant run's outcome from its engine, once the run is over: the
// contacts' records, the impact's span (the times of the series, frames and peaks from its
// start), the bodies' velocities and the counts.
void assemble(const CompliantEngine& engine, const ContactModel& model, CompliantRun& run) {
  ImpactOutcome& impact = run.impact;
  numerics::ImpactResult& result = impact.result;
  const ImpactSpan span = engine.impact_span();
  impact.impact_time = span.start;
  const Eigen::Index m = model.contact_count();
  for (Eigen::VectorXd* v : {&result.impulse, &result.max_force, &result.time_of_max_force,
                             &result.work, &result.stored_energy, &impact.stored_energy_at_start})
    v->resize(m);
  for (Eigen::Index c = 0; c < m; ++c) {
    const ContactTotals totals = engine.totals(c);
    result.impulse(c) = totals.impulse;
    result.max_force(c) = totals.max_force;
    result.time_of_max_force(c) = totals.time_of_max_force - span.start;
    result.work(c) = totals.work;
    result.stored_energy(c) = totals.stored_energy;
    impact.stored_energy_at_start(c) = totals.stored_energy_at_start;
  }
  result.steps = engine.steps();
  result.duration = span.end - span.start;
  impact.work_of_forces = engine.work_of_forces();
  impact.formed = engine.formed_contacts(m);
  impact.cut_by_end_time = span.cut_by_end_time;
  const int d = model.dimension;
  impact.velocity_after.resize(model.mass.size());
  for (Eigen::Index b = 0; b < model.body_count(); ++b)
    impact.velocity_after.segment(b * d, d) = engine.velocity(b).head(d);
  result.velocity = model.W.transpose() * impact.velocity_after;
  if (engine.has_positions()) {
    impact.position_after.resize(model.mass.size());
    for (Eigen::Index b = 0; b < model.body_count(); ++b)
      impact.position_after.segment(b * d, d) = engine.position(b).head(d);
  }
  if (model.rotation) add_rotation(engine, model, impact);
  impact.impact_times = {span.start};
  impact.velocities_before = {model.velocity};
  run.most_bodies_in_motion = engine.most_bodies_in_motion();
  run.moving = engine.moving_stats();
  for (double& t : run.series.time) t -= span.start;
  for (double& t : run.frames.time) t -= span.start;
}

}  // namespace

CompliantRun simulate_compliant(const ContactModel& model,
                                std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                                const CompliantSpec& spec, const CompliantRunOptions& options) {
  const RecordSpec& record = options.record;
  const int frame_every = options.frame_every;
  const double end = spec.end_time.value_or(1.0);
  const bool recording = !record.contacts.empty() || !record.bodies.empty() || frame_every > 0;
  RecordingBudget budget = compliant_budget(model, record, frame_every, options.limits);
  if (recording) {
    // samples from t = 0 to the first arrival and through the shortest possible impact
    const double samples =
        (*std::min_element(model.striker_arrivals.begin(), model.striker_arrivals.end()) +
         impact_duration_bound(model)) /
        record.interval;
    budget.check_estimate(samples, frame_every > 0 ? samples / double(frame_every) : 0.0);
  }
  const auto clock = std::chrono::steady_clock::now();
  const std::unique_ptr<CompliantEngine> engine =
      make_compliant_engine(model, std::move(system), spec);
  engine->set_progress(options.progress);
  CompliantRun run;
  run.series.contacts = record.contacts;
  run.series.bodies = record.bodies;
  run.series.dimension = model.dimension;
  if (recording)
    granular::record(*engine, model, {record, frame_every, end, std::move(budget)}, run);
  else
    engine->advance_to(end);
  engine->finish();
  run.impact.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
  assemble(*engine, model, run);
  return run;
}

}  // namespace mimpact::granular
