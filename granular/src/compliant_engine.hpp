#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <memory>

#include "mimpact/granular/contact_model.hpp"
#include "mimpact/granular/impact_outcome.hpp"
#include "mimpact/granular/moving_contacts_stats.hpp"
#include "mimpact/granular/progress_meter.hpp"
#include "mimpact/granular/scene_spec.hpp"
#include "mimpact/kernel/non_smooth_dynamical_system.hpp"

namespace mimpact::granular {

// One contact's record over a compliant run.
struct ContactTotals {
  double impulse = 0.0;                 // N s
  double max_force = 0.0;               // N
  double time_of_max_force = 0.0;       // s, on the run's clock
  double work = 0.0;                    // J taken from the bodies (the integral of -u dP)
  double stored_energy = 0.0;           // J held now
  double stored_energy_at_start = 0.0;  // J held at the start (a precompressed scene's)
  // with friction: N s along the contact's tangent rows (Rotation::tangential), and the work its
  // tangential force took (J, beside `work`, the normal force's)
  Eigen::Vector2d tangential_impulse = Eigen::Vector2d::Zero();
  double slip_work = 0.0;
};

// Where the impact lies in a compliant run, on the run's clock (s).
struct ImpactSpan {
  double start = 0.0, end = 0.0;
  bool cut_by_end_time = false;  // the run ended before the contacts were done
};

// The compliant contacts integrated in time, whichever engine integrates them: the moving
// geometry (MovingContacts, the beads where they are) or the kernel's CompliantIntegrator under
// kernel::Simulation (the frozen geometry, and scenes without beads). The one recorder loop and
// the one assembly of the outcome (simulate_compliant) read both through this.
class CompliantEngine {
 public:
  virtual ~CompliantEngine() = default;

  // Integrates to `t` (s, >= time()), or until ended().
  virtual void advance_to(double t) = 0;
  // Tells `progress` (null: nothing) where it is as it integrates.
  virtual void set_progress(ProgressMeter* progress) = 0;
  // Ends the run: what follows is final.
  virtual void finish() {}
  virtual double time() const = 0;
  // The contacts are done: nothing but free flights would change.
  virtual bool ended() const = 0;

  virtual double force(Eigen::Index contact) const = 0;  // N, now
  virtual ContactTotals totals(Eigen::Index contact) const = 0;
  virtual Eigen::Vector3d velocity(Eigen::Index body) const = 0;  // m/s
  // rad/s, of a body that turns (its model has a Rotation): its `components` first, else 0
  virtual Eigen::Vector3d angular_velocity(Eigen::Index body) const = 0;
  // Whether position() says where the bodies are: not in the frozen geometry, whose
  // configuration is the impact's.
  virtual bool has_positions() const = 0;
  virtual Eigen::Vector3d position(Eigen::Index body) const = 0;  // m

  // After finish(): the impact's span, the integration's steps, the work of the bodies' own
  // forces (J), the most bodies integrated at once and the moving geometry's counts (zero in
  // the frozen one).
  virtual ImpactSpan impact_span() const = 0;
  virtual std::int64_t steps() const = 0;
  virtual double work_of_forces() const = 0;
  // The contacts formed beyond the model's first `model_contacts` (none unless the bodies move).
  virtual FormedContacts formed_contacts(Eigen::Index /*model_contacts*/) const { return {}; }
  virtual Eigen::Index most_bodies_in_motion() const = 0;
  virtual MovingContactsStats moving_stats() const { return {}; }
};

// The engine `spec` chooses for `model`: the moving geometry where the model has beads and the
// spec asks for it, else the kernel's over `system`, each with the tolerances spec.tolerance
// maps to (compliant_engines.cpp).
std::unique_ptr<CompliantEngine> make_compliant_engine(
    const ContactModel& model, std::shared_ptr<kernel::NonSmoothDynamicalSystem> system,
    const CompliantSpec& spec);

}  // namespace mimpact::granular
