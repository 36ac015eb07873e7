#include "mimpact/granular/impact_runs.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "mimpact/common/error.hpp"
#include "mimpact/granular/impact_recorder.hpp"
#include "mimpact/granular/moving_contacts.hpp"
#include "mimpact/kernel/simulation.hpp"
#include "mimpact/plugins/acceleration_lcp_problem.hpp"
#include "mimpact/plugins/compliant_integrator.hpp"
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
    total_.velocity = model_.W.transpose() * result_.velocity_after;
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
    total_.steps += impact.steps;
    total_.contact_steps += impact.contact_steps;
    total_.residual_energy += impact.residual_energy;
    total_.duration = offset + impact.duration;
    result_.wall_time += report.wall_time;
    result_.impact_times.push_back(report.time);
    result_.velocities_before.push_back(report.generalized_velocity_before);
    result_.velocity_after = report.generalized_velocity_after;
  }

  const ContactModel& model_;
  double last_arrival_;
  numerics::ImpactResult total_;
  ImpactOutcome result_;
};

// Samples the recorded contacts and bodies of a compliant run, and every frame_every-th sample
// the whole scene; ends a free scene once it has come apart.
class CompliantWatch : public kernel::SimulationObserver {
 public:
  CompliantWatch(const RecordSpec& record, int dimension, int frame_every, bool precompressed,
                 bool touching_at_start, RecordingBudget budget)
      : record_(record),
        frame_every_(frame_every),
        precompressed_(precompressed),
        budget_(std::move(budget)) {
    // a striker with no gap touches at t = 0: the impact starts at once, with no closing event
    if (touching_at_start) first_contact_ = 0.0;
    series_.contacts = record.contacts;
    series_.bodies = record.bodies;
    series_.dimension = dimension;
  }

  void on_output(const kernel::Simulation& s) override {
    const kernel::ContactForceHistory& history = *s.integrator().contact_force_history();
    const kernel::NonSmoothDynamicalSystem& system = s.system();
    series_.time.push_back(s.time());
    std::vector<double> forces, velocities;
    for (int c : record_.contacts) forces.push_back(history.force(c));
    for (int b : record_.bodies)
      for (double v : system.system(b).velocity()) velocities.push_back(v);
    series_.force.push_back(forces);
    series_.velocity.push_back(velocities);
    const bool frame =
        frame_every_ > 0 && (series_.time.size() - 1) % std::size_t(frame_every_) == 0;
    budget_.add(frame);
    if (frame) {
      frames_.time.push_back(s.time());
      frames_.force.emplace_back(history.force.data(), history.force.data() + history.force.size());
      std::vector<double> all;
      for (kernel::Index b = 0; b < system.system_count(); ++b)
        for (double v : system.system(b).velocity()) all.push_back(v);
      frames_.velocity.push_back(std::move(all));
    }
  }

  kernel::EventStatus on_step(const kernel::Simulation& s,
                              const kernel::StepReport& step) override {
    if (!step.closing.empty() && first_contact_ < 0.0) first_contact_ = step.time;
    if (!step.detaching.empty()) last_opening_ = step.time;
    if (!precompressed_ && first_contact_ >= 0.0 &&
        s.integrator().contact_force_history()->all_open)
      return kernel::EventStatus::terminate("the scene has come apart");
    return kernel::EventStatus::proceed();
  }

  double first_contact() const { return first_contact_; }
  double last_opening() const { return last_opening_; }
  TimeSeries take_series() { return std::move(series_); }
  Frames take_frames() { return std::move(frames_); }

 private:
  const RecordSpec& record_;
  int frame_every_;
  bool precompressed_;
  TimeSeries series_;
  Frames frames_;
  RecordingBudget budget_;
  double first_contact_ = -1.0, last_opening_ = -1.0;
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

// Overlaps below this share of the impact's are never integrated (CompliantOptions): their
// force is below 1e-18 of the peak force. A contact joining at an overlap rho misses an
// impulse K rho^2.5 / (2.5 w) at approach speed w: at 1e-6 of the overlap (this floor before
// issue 24) a chain's late, slow recontacts moved its beads by 5e-11 of the strike's speed,
// which the tightest tolerances resolve (tests/packings/test_packing_reduction.cpp).
constexpr double kOverlapResolution = 1e-12;

// The impact's overlap, or the static one of a precompressed scene struck by nothing.
double overlap_scale(const ContactModel& model) {
  const double overlap = impact_overlap(model);
  return std::isfinite(overlap) ? overlap : std::max(model.largest_static_overlap, 1e-6);
}

}  // namespace

ImpactOutcome simulate_impacts(const ContactModel& model,
                               std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                               const plugins::LzbImpactOptions& options,
                               numerics::ImpactObserver* observer) {
  auto impacts = std::make_unique<plugins::LzbImpactProblem>(options);
  impacts->set_impact_observer(observer);
  kernel::Simulation simulation(
      std::move(system), std::make_unique<plugins::EventDrivenIntegrator>(),
      {.impacts = std::move(impacts),
       .contact_forces = std::make_unique<plugins::AccelerationLcpProblem>()});
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
  impact.result = integrator.integrate(model.H, model.u_minus, model.laws, observer);
  impact.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  impact.velocity_after =
      model.velocity + (model.W * impact.result.impulse).cwiseQuotient(model.mass);
  impact.impact_times = {0.0};
  impact.velocities_before = {model.velocity};
  return impact;
}

namespace {

// The compliant integration's error control, whichever geometry: the relative tolerance, the
// positions' absolute one (m) and the overlap a contact joins at (m).
struct CompliantTolerances {
  double relative, absolute, resolution;
};

CompliantTolerances compliant_tolerances(const ContactModel& model, const CompliantSpec& spec) {
  const double tolerance = spec.tolerance;  // within [1e-14, 1e-4] (CompliantSpec)
  // A contact approaching at tolerance x V holds tolerance^(2 / (1 + eta)) of the impact's
  // overlap: overlaps up to ten times that are the integration's own error (its velocities
  // carry tolerance x V), not worth integrating.
  const double overlap = overlap_scale(model);
  const double resolution =
      std::max(kOverlapResolution,
               10.0 * std::pow(tolerance, 2.0 / (1.0 + model.laws.front().exponent))) *
      overlap;
  // the positions to the tolerance's share of the impact's overlap
  return {tolerance, 1e-2 * tolerance * overlap, resolution};
}

// The compliant contacts where the bodies are (MovingContacts), sampled every record.interval.
CompliantRun simulate_moving(const ContactModel& model, const CompliantSpec& spec,
                             const RecordSpec& record, int frame_every, const RunLimits& limits) {
  const CompliantTolerances tolerances = compliant_tolerances(model, spec);
  MovingContactsOptions options;
  options.ode.relative_tolerance = tolerances.relative;
  // The Nystrom pair's steps are set by the contacts' impulses since their group's last restart,
  // small numbers held to the absolute tolerance: a tenth of the tolerance's share of the
  // impact's overlap rather than a hundredth takes 8 to 29 % fewer body steps at equal accuracy
  // (docs/design/moving_geometry.md).
  options.ode.absolute_tolerance = 10.0 * tolerances.absolute;
  options.ode.event_tolerance = 1e-13;
  // A contact left out below an overlap r for a window (a quarter of a contact's duration)
  // changes the velocities by about (r / overlap)^eta V / 4: the moving geometry resolves
  // overlaps down to (1e-2 tolerance)^(1 / eta) of the impact's, so that this stays under the
  // error the tolerance allows (at 1e-4: RMS 4.4e-5 on 32 x 32, from 3.5e-4 with the frozen
  // integrator's resolution, for the same time).
  options.overlap_resolution =
      std::max(kOverlapResolution,
               std::pow(1e-2 * tolerances.relative, 1.0 / model.laws.front().exponent)) *
      overlap_scale(model);
  options.max_steps = spec.max_steps;
  const int d = model.dimension;
  std::vector<Eigen::Vector3d> velocity(std::size_t(model.body_count()), Eigen::Vector3d::Zero());
  for (Eigen::Index b = 0; b < model.body_count(); ++b)
    velocity[std::size_t(b)].head(d) = model.velocity.segment(d * b, d);
  const auto clock = std::chrono::steady_clock::now();
  MovingContacts motion(*model.beads, velocity, model.beads->closed, options);
  const double end = spec.end_time.value_or(1.0);
  const bool recording = !record.contacts.empty() || !record.bodies.empty() || frame_every > 0;
  CompliantRun run;
  run.series.contacts = record.contacts;
  run.series.bodies = record.bodies;
  run.series.dimension = d;
  const double impact_time =
      *std::min_element(model.striker_arrivals.begin(), model.striker_arrivals.end());
  if (recording) {
    RecordingBudget budget = compliant_budget(model, record, frame_every, limits);
    const double samples = (impact_time + impact_duration_bound(model)) / record.interval;
    budget.check_estimate(samples, frame_every > 0 ? samples / double(frame_every) : 0.0);
    for (std::int64_t k = 0;; ++k) {
      const double t = std::min(end, double(k) * record.interval);
      motion.advance(t);
      run.series.time.push_back(motion.time() - impact_time);
      std::vector<double> forces, velocities;
      for (int c : record.contacts) forces.push_back(motion.contacts()[std::size_t(c)].force);
      for (int b : record.bodies)
        for (int i = 0; i < d; ++i) velocities.push_back(motion.velocity(b)(i));
      run.series.force.push_back(std::move(forces));
      run.series.velocity.push_back(std::move(velocities));
      const bool frame = frame_every > 0 && k % frame_every == 0;
      budget.add(frame);
      if (frame) {
        run.frames.time.push_back(motion.time() - impact_time);
        std::vector<double> all_forces, all_velocities, all_positions;
        for (Eigen::Index c = 0; c < model.contact_count(); ++c)
          all_forces.push_back(motion.contacts()[std::size_t(c)].force);
        for (Eigen::Index b = 0; b < model.body_count(); ++b)
          for (int i = 0; i < d; ++i) {
            all_velocities.push_back(motion.velocity(b)(i));
            all_positions.push_back(motion.position(b)(i));
          }
        run.frames.force.push_back(std::move(all_forces));
        run.frames.velocity.push_back(std::move(all_velocities));
        run.frames.position.push_back(std::move(all_positions));
      }
      if (t >= end || motion.ended()) break;
    }
  } else {
    motion.advance(end);
  }
  ImpactOutcome& impact = run.impact;
  impact.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
  impact.impact_time = impact_time;
  const Eigen::Index m = model.contact_count();
  numerics::ImpactResult& result = impact.result;
  result.impulse.resize(m);
  result.max_force.resize(m);
  result.time_of_max_force.resize(m);
  result.work.resize(m);
  result.stored_energy.resize(m);
  for (Eigen::Index c = 0; c < m; ++c) {
    const MovingContact& contact = motion.contacts()[std::size_t(c)];
    result.impulse(c) = contact.impulse;
    result.max_force(c) = contact.max_force;
    result.time_of_max_force(c) = contact.time_of_max_force - impact_time;
    result.work(c) = contact.work();
    result.stored_energy(c) = contact.stored_energy;
  }
  result.steps = motion.stats().steps;
  result.duration = motion.time() - impact_time;
  impact.stored_energy_at_start = Eigen::VectorXd::Zero(m);
  impact.cut_by_end_time = !motion.ended();
  impact.velocity_after.resize(model.mass.size());
  for (Eigen::Index b = 0; b < model.body_count(); ++b)
    impact.velocity_after.segment(b * d, d) = motion.velocity(b).head(d);
  result.velocity = model.W.transpose() * impact.velocity_after;
  impact.impact_times = {impact_time};
  impact.velocities_before = {model.velocity};
  run.most_bodies_in_motion = motion.stats().most_bodies_in_motion;
  run.moving = motion.stats();
  return run;
}

}  // namespace

CompliantRun simulate_compliant(const ContactModel& model,
                                std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
                                const CompliantSpec& spec, const RecordSpec& record,
                                int frame_every, const RunLimits& limits) {
  if (spec.geometry == Geometry::moving && model.beads)
    return simulate_moving(model, spec, record, frame_every, limits);
  const auto [tolerance, absolute_tolerance, resolution] = compliant_tolerances(model, spec);
  plugins::CompliantOptions options;
  options.ode.relative_tolerance = tolerance;
  options.ode.absolute_tolerance = absolute_tolerance;
  options.overlap_resolution = resolution;
  options.frozen_gaps = spec.gaps == Gaps::frozen;
  options.max_steps = spec.max_steps;
  auto integrator = std::make_unique<plugins::CompliantIntegrator>(options);
  const plugins::CompliantIntegrator& compliant = *integrator;
  kernel::SimulationOptions simulation_options;
  simulation_options.penetration_tolerance += model.largest_static_overlap;  // precompressed
  kernel::Simulation simulation(system, std::move(integrator), {}, simulation_options);
  const double end = spec.end_time.value_or(1.0);
  const bool recording = !record.contacts.empty() || !record.bodies.empty() || frame_every > 0;
  RecordingBudget budget = compliant_budget(model, record, frame_every, limits);
  if (recording) {
    // samples from t = 0 to the first arrival and through the shortest possible impact
    const double samples =
        (*std::min_element(model.striker_arrivals.begin(), model.striker_arrivals.end()) +
         impact_duration_bound(model)) /
        record.interval;
    budget.check_estimate(samples, frame_every > 0 ? samples / double(frame_every) : 0.0);
    simulation.schedule_outputs(0.0, record.interval, end);
  }
  const bool precompressed = model.precompression > 0.0;
  CompliantWatch watch(record, model.dimension, frame_every, precompressed,
                       std::find(model.striker_arrivals.begin(), model.striker_arrivals.end(),
                                 0.0) != model.striker_arrivals.end(),
                       std::move(budget));
  simulation.add_observer(watch);
  const auto clock = std::chrono::steady_clock::now();
  const kernel::RunSummary summary = simulation.run(0.0, end);
  const kernel::ContactForceHistory& history = *simulation.integrator().contact_force_history();

  CompliantRun run;
  ImpactOutcome& impact = run.impact;
  impact.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count();
  // touching strikers start in contact: no closing event, the impact begins at 0
  impact.impact_time = std::max(0.0, watch.first_contact());
  impact.result.impulse = history.impulse;
  impact.result.max_force = history.max_force;
  impact.result.time_of_max_force = history.time_of_max_force.array() - impact.impact_time;
  impact.result.steps = summary.smooth_steps;
  impact.result.work = history.work;
  impact.result.stored_energy = history.stored_energy;
  impact.stored_energy_at_start = history.stored_energy_at_start;
  impact.work_of_forces = history.work_of_forces;
  impact.cut_by_end_time = !precompressed && !history.all_open;
  // a free scene's impact lasts until its last contact opens; a precompressed one's, the run
  impact.result.duration =
      (precompressed || watch.last_opening() < 0.0 ? summary.end_time : watch.last_opening()) -
      impact.impact_time;
  impact.velocity_after.resize(model.mass.size());
  for (Eigen::Index b = 0; b < model.body_count(); ++b)
    impact.velocity_after.segment(b * model.dimension, model.dimension) =
        system->system(b).velocity();
  impact.result.velocity = model.W.transpose() * impact.velocity_after;
  impact.impact_times = {impact.impact_time};
  impact.velocities_before = {model.velocity};
  run.series = watch.take_series();
  run.frames = watch.take_frames();
  run.most_bodies_in_motion = compliant.most_bodies_in_motion();
  for (double& t : run.series.time) t -= impact.impact_time;
  for (double& t : run.frames.time) t -= impact.impact_time;
  return run;
}

}  // namespace mimpact::granular
