// The two engines of the compliant contacts behind CompliantEngine, and what the scene's
// tolerance asks of each.
#include <algorithm>
#include <cmath>
#include <vector>

#include "compliant_engine.hpp"
#include "mimpact/granular/moving_contacts.hpp"
#include "mimpact/granular/rotation.hpp"
#include "mimpact/kernel/simulation.hpp"
#include "mimpact/plugins/compliant_integrator.hpp"

namespace mimpact::granular {

namespace {

// Overlaps below this share of the impact's are never integrated (CompliantOptions): their
// force is below 1e-18 of the peak force. A contact joining at an overlap rho misses an
// impulse K rho^2.5 / (2.5 w) at approach speed w, which this floor keeps below what the
// tightest tolerances resolve (tests/packings/test_packing_reduction.cpp).
constexpr double kOverlapResolution = 1e-12;

// The impact's overlap, or the static one of a precompressed scene struck by nothing.
double overlap_scale(const ContactModel& model) {
  const double overlap = impact_overlap(model);
  return std::isfinite(overlap) ? overlap : std::max(model.largest_static_overlap, 1e-6);
}

// The compliant integration's error control for one engine: the relative tolerance, the
// positions' absolute one (m) and the overlap a contact joins at (m).
struct CompliantTolerances {
  double relative, absolute, resolution;
};
enum class Engine { kernel, moving };

// The one mapping from the scene's tolerance to each engine's error control. The two engines
// leave a contact below the joining overlap r out in different ways, so r follows from the
// tolerance by two rules (docs/design/compliant_contacts.md, docs/design/moving_geometry.md):
// - the kernel's engine leaves a contact out only until its overlap reaches r (one approaching
//   slower than tolerance x V collides at once instead): a contact approaching at tolerance x V
//   holds tolerance^(2 / (1 + eta)) of the impact's overlap, and overlaps up to ten times that
//   are the integration's own error (its velocities carry tolerance x V);
// - the moving geometry leaves a contact out below r for a window (a quarter of a contact's
//   duration), which changes the velocities by about (r / overlap)^eta V / 4: it resolves
//   overlaps down to (1e-2 tolerance)^(1 / eta) of the impact's, so that this stays under the
//   error the tolerance allows.
// Either rule in the other engine costs accuracy or time (docs/design/compliant_contacts.md,
// "Trials not kept").
CompliantTolerances compliant_tolerances(const ContactModel& model, const CompliantSpec& spec,
                                         Engine engine) {
  const double tolerance = spec.tolerance;  // within [1e-14, 1e-4] (CompliantSpec)
  const double overlap = overlap_scale(model);
  const double exponent = model.laws.front().exponent;
  // the positions to the tolerance's share of the impact's overlap; the Nystrom pair's steps
  // are set by the contacts' impulses since their group's last restart, small numbers held to
  // the absolute tolerance, and a tenth of that share rather than a hundredth takes fewer body
  // steps at equal accuracy (docs/design/moving_geometry.md)
  const double absolute = 1e-2 * tolerance * overlap;
  if (engine == Engine::moving)
    return {tolerance, 10.0 * absolute,
            std::max(kOverlapResolution, std::pow(1e-2 * tolerance, 1.0 / exponent)) * overlap};
  return {
      tolerance, absolute,
      std::max(kOverlapResolution, 10.0 * std::pow(tolerance, 2.0 / (1.0 + exponent))) * overlap};
}

MovingContactsOptions moving_options(const ContactModel& model, const CompliantSpec& spec) {
  const CompliantTolerances tolerances = compliant_tolerances(model, spec, Engine::moving);
  MovingContactsOptions options;
  options.ode.relative_tolerance = tolerances.relative;
  options.ode.absolute_tolerance = tolerances.absolute;
  options.ode.event_tolerance = 1e-13;
  options.overlap_resolution = tolerances.resolution;
  options.max_steps = spec.max_steps;
  options.max_body_steps = spec.max_body_steps;
  return options;
}

// Hertz's law holds for overlaps small beside the radii: an approaching contact whose lone
// overlap (lone_overlap), with its bodies' spin energy I w^2 / 2 added to its approach (friction
// may turn the one into the other), exceeds half the smaller radius of its bodies is refused, its
// beads would pass through each other (a striker at 1e8 m/s, or spinning at 9e18 rad/s, ran
// past 10 s).
void check_overlaps_within_radii(const ContactModel& model) {
  for (Eigen::Index j = 0; j < model.contact_count(); ++j) {
    if (!(model.u_minus(j) < 0.0)) continue;
    double radius = INFINITY, spin_energy = 0.0;
    std::string bodies;
    Eigen::Index last = -1;
    for (Eigen::SparseMatrix<double>::InnerIterator it(model.W, j); it; ++it) {
      const Eigen::Index body = it.row() / model.dimension;  // rows by body, then component
      if (body == last) continue;
      last = body;
      radius = std::min(radius, model.beads->radius(body));
      bodies += (bodies.empty() ? "body " : " and body ") + std::to_string(body);
      if (model.rotation)
        spin_energy += 0.5 * model.rotation->inertia(body) *
                       model.rotation->of(model.rotation->angular_velocity, body).squaredNorm();
    }
    const numerics::ContactLaw& law = model.laws[std::size_t(j)];
    const double approach = 0.5 * model.u_minus(j) * model.u_minus(j) / model.H.coeff(j, j);
    const double overlap =
        spin_energy > 0.0
            ? std::pow((1.0 + law.exponent) * (approach + spin_energy) / law.stiffness,
                       1.0 / (1.0 + law.exponent))
            : lone_overlap(model, j);
    if (overlap > 0.5 * radius)
      throw InvalidInput(
          "the strikers' speeds" + std::string(spin_energy > 0.0 ? " and spins" : "") + " press " +
          bodies + " about " + to_text(overlap) +
          " m into each other, more than half their smaller radius (" + to_text(radius) +
          " m): Hertz's law holds for overlaps small beside the radii; allowed: slower strikers "
          "(strikers[].velocity" +
          std::string(spin_energy > 0.0 ? ", strikers[].spin" : "") +
          "), or the LZB impact (\"method\": \"lzb\"), whose configuration is frozen");
  }
}

// The beads where they are (MovingContacts); the impact starts with the first striker's arrival.
class MovingEngine : public CompliantEngine {
 public:
  MovingEngine(const ContactModel& model, const CompliantSpec& spec)
      : motion_(*model.beads, velocities(model), model.beads->closed, moving_options(model, spec),
                spins(model)),
        impact_time_(
            *std::min_element(model.striker_arrivals.begin(), model.striker_arrivals.end())),
        dimension_(model.dimension) {}

  void advance_to(double t) override { motion_.advance(t); }
  void set_progress(ProgressMeter* progress) override { motion_.set_progress(progress); }
  double time() const override { return motion_.time(); }
  bool ended() const override { return motion_.ended(); }
  double force(Eigen::Index contact) const override {
    return motion_.contacts()[std::size_t(contact)].force;
  }
  ContactTotals totals(Eigen::Index contact) const override {
    const MovingContact& c = motion_.contacts()[std::size_t(contact)];
    ContactTotals totals{.impulse = c.impulse,
                         .max_force = c.max_force,
                         .time_of_max_force = c.time_of_max_force,
                         .work = c.work(),
                         .stored_energy = c.stored_energy,
                         .slip_work = c.slip_work};
    // along the tangent rows of the contact's normal at the start (Rotation): its impulse is
    // the second body's, a wall's bead counted as the second
    if (c.tangential_impulse.squaredNorm() > 0.0) {
      const BeadGeometry& beads = motion_.geometry();
      const Eigen::Vector3d normal =
          c.wall() ? beads.walls[std::size_t(-1 - c.second)].normal
                   : (beads.position[std::size_t(c.second)] - beads.position[std::size_t(c.first)])
                         .normalized();
      Eigen::Vector3d tangents[2];
      const int rows = tangent_frame(normal, dimension_, tangents);
      for (int r = 0; r < rows; ++r)
        totals.tangential_impulse(r) =
            (c.wall() ? -1.0 : 1.0) * tangents[r].dot(c.tangential_impulse);
    }
    return totals;
  }
  Eigen::Vector3d velocity(Eigen::Index body) const override { return motion_.velocity(body); }
  // about z in the plane: the model's one component
  Eigen::Vector3d angular_velocity(Eigen::Index body) const override {
    const Eigen::Vector3d omega = motion_.angular_velocity(body);
    return dimension_ == 3 ? omega : Eigen::Vector3d(omega(2), 0.0, 0.0);
  }
  bool has_positions() const override { return true; }
  Eigen::Vector3d position(Eigen::Index body) const override { return motion_.position(body); }
  ImpactSpan impact_span() const override {
    return {.start = impact_time_, .end = motion_.time(), .cut_by_end_time = !motion_.ended()};
  }
  std::int64_t steps() const override { return motion_.stats().steps; }
  double work_of_forces() const override { return 0.0; }
  FormedContacts formed_contacts(Eigen::Index model_contacts) const override {
    FormedContacts formed;
    const std::vector<MovingContact>& contacts = motion_.contacts();
    for (std::size_t id = std::size_t(model_contacts); id < contacts.size(); ++id) {
      ++formed.count;
      formed.dissipated += contacts[id].dissipated + contacts[id].slip_work;
      formed.potential_left += contacts[id].stored_energy;
    }
    return formed;
  }
  Eigen::Index most_bodies_in_motion() const override {
    return motion_.stats().most_bodies_in_motion;
  }
  MovingContactsStats moving_stats() const override { return motion_.stats(); }

 private:
  static std::vector<Eigen::Vector3d> velocities(const ContactModel& model) {
    const int d = model.dimension;
    std::vector<Eigen::Vector3d> velocity(std::size_t(model.body_count()), Eigen::Vector3d::Zero());
    for (Eigen::Index b = 0; b < model.body_count(); ++b)
      velocity[std::size_t(b)].head(d) = model.velocity.segment(d * b, d);
    return velocity;
  }

  // the model's angular velocities as 3-vectors (about z in the plane)
  static std::vector<Eigen::Vector3d> spins(const ContactModel& model) {
    if (!model.rotation) return {};
    const Rotation& rotation = *model.rotation;
    std::vector<Eigen::Vector3d> spin(std::size_t(model.body_count()), Eigen::Vector3d::Zero());
    for (Eigen::Index b = 0; b < model.body_count(); ++b) {
      if (rotation.components == 3)
        spin[std::size_t(b)] = rotation.of(rotation.angular_velocity, b);
      else
        spin[std::size_t(b)](2) = rotation.angular_velocity(b);
    }
    return spin;
  }

  MovingContacts motion_;
  double impact_time_;  // s
  int dimension_;
};

// When the impact starts and its last contact opens; ends a free scene once it has come apart.
class ContactWatch : public kernel::SimulationObserver {
 public:
  ContactWatch(bool precompressed, bool touching_at_start) : precompressed_(precompressed) {
    // a striker with no gap touches at t = 0: the impact starts at once, with no closing event
    if (touching_at_start) first_contact_ = 0.0;
  }

  kernel::EventStatus on_step(const kernel::Simulation& s,
                              const kernel::StepReport& step) override {
    steps_ += step.smooth_steps;
    if (progress_) progress_->report({.time = step.time, .steps = steps_});
    if (!step.closing.empty() && first_contact_ < 0.0) first_contact_ = step.time;
    if (!step.detaching.empty()) last_opening_ = step.time;
    if (!precompressed_ && first_contact_ >= 0.0 &&
        s.integrator().contact_force_history()->all_open) {
      ended_ = true;
      return kernel::EventStatus::terminate("the scene has come apart");
    }
    return kernel::EventStatus::proceed();
  }

  void set_progress(ProgressMeter* progress) { progress_ = progress; }
  bool precompressed() const { return precompressed_; }
  bool ended() const { return ended_; }
  double first_contact() const { return first_contact_; }
  double last_opening() const { return last_opening_; }

 private:
  bool precompressed_, ended_ = false;
  double first_contact_ = -1.0, last_opening_ = -1.0;
  std::int64_t steps_ = 0;
  ProgressMeter* progress_ = nullptr;
};

std::unique_ptr<plugins::CompliantIntegrator> kernel_integrator(const ContactModel& model,
                                                                const CompliantSpec& spec) {
  const CompliantTolerances tolerances = compliant_tolerances(model, spec, Engine::kernel);
  plugins::CompliantOptions options;
  options.ode.relative_tolerance = tolerances.relative;
  options.ode.absolute_tolerance = tolerances.absolute;
  options.overlap_resolution = tolerances.resolution;
  options.frozen_gaps = spec.gaps == Gaps::frozen;
  options.max_steps = spec.max_steps;
  return std::make_unique<plugins::CompliantIntegrator>(options);
}

// The kernel's CompliantIntegrator over the model's system; the impact starts with the first
// contact, and a free scene's ends where its last contact opens (a precompressed one's, with the
// run).
class KernelEngine : public CompliantEngine {
 public:
  KernelEngine(const ContactModel& model, std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
               const CompliantSpec& spec)
      : dimension_(model.dimension),
        integrator_(kernel_integrator(model, spec).release()),
        simulation_(std::move(system), std::unique_ptr<plugins::CompliantIntegrator>(integrator_),
                    {}, simulation_options(model)),
        watch_(model.precompression > 0.0,
               std::find(model.striker_arrivals.begin(), model.striker_arrivals.end(), 0.0) !=
                   model.striker_arrivals.end()) {
    simulation_.add_observer(watch_);
    simulation_.initialize(0.0);
  }

  void advance_to(double t) override { simulation_.advance_to(t); }
  void set_progress(ProgressMeter* progress) override { watch_.set_progress(progress); }
  void finish() override { summary_ = simulation_.finish(); }
  double time() const override { return simulation_.time(); }
  bool ended() const override { return watch_.ended(); }
  double force(Eigen::Index contact) const override { return history().force(contact); }
  ContactTotals totals(Eigen::Index contact) const override {
    const kernel::ContactForceHistory& h = history();
    ContactTotals totals{.impulse = h.impulse(contact),
                         .max_force = h.max_force(contact),
                         .time_of_max_force = h.time_of_max_force(contact),
                         .work = h.work(contact),
                         .stored_energy = h.stored_energy(contact),
                         .stored_energy_at_start = h.stored_energy_at_start(contact)};
    if (h.slip_work.size() > 0) {
      totals.tangential_impulse = h.tangential_impulse.row(contact).transpose();
      totals.slip_work = h.slip_work(contact);
    }
    return totals;
  }
  // a body's generalized velocity is [v (d), omega (r)] where it turns (build_packing_system)
  Eigen::Vector3d velocity(Eigen::Index body) const override {
    const Eigen::VectorXd& v = simulation_.system().system(body).velocity();
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
    velocity.head(dimension_) = v.head(dimension_);
    return velocity;
  }
  Eigen::Vector3d angular_velocity(Eigen::Index body) const override {
    const Eigen::VectorXd& v = simulation_.system().system(body).velocity();
    Eigen::Vector3d omega = Eigen::Vector3d::Zero();
    omega.head(v.size() - dimension_) = v.tail(v.size() - dimension_);
    return omega;
  }
  bool has_positions() const override { return false; }
  Eigen::Vector3d position(Eigen::Index) const override { return Eigen::Vector3d::Zero(); }
  ImpactSpan impact_span() const override {
    const double start = std::max(0.0, watch_.first_contact());
    const double end = watch_.precompressed() || watch_.last_opening() < 0.0
                           ? summary_.end_time
                           : watch_.last_opening();
    return {.start = start,
            .end = end,
            .cut_by_end_time = !watch_.precompressed() && !history().all_open};
  }
  std::int64_t steps() const override { return summary_.smooth_steps; }
  double work_of_forces() const override { return history().work_of_forces; }
  Eigen::Index most_bodies_in_motion() const override {
    return integrator_->most_bodies_in_motion();
  }

 private:
  const kernel::ContactForceHistory& history() const {
    return *simulation_.integrator().contact_force_history();
  }

  int dimension_;
  plugins::CompliantIntegrator* integrator_;  // owned by simulation_
  kernel::Simulation simulation_;
  ContactWatch watch_;
  kernel::RunSummary summary_;
};

}  // namespace

std::unique_ptr<CompliantEngine> make_compliant_engine(
    const ContactModel& model, std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
    const CompliantSpec& spec) {
  if (spec.geometry == Geometry::moving && model.beads) {
    check_overlaps_within_radii(model);
    return std::make_unique<MovingEngine>(model, spec);  // MovingContacts checks their rounding
  }
  double largest_coordinate = 0.0;
  for (Eigen::Index b = 0; b < system->system_count(); ++b)
    largest_coordinate =
        std::max(largest_coordinate,
                 system->system(b).position().head(model.dimension).lpNorm<Eigen::Infinity>());
  check_overlap_resolved(overlap_scale(model), largest_coordinate, faster_strikers_advice(false));
  return std::make_unique<KernelEngine>(model, std::move(system), spec);
}

}  // namespace mimpact::granular
