#pragma once

#include <Eigen/Dense>
#include <optional>
#include <string>

#include "mimpact/common/fields.hpp"
#include "mimpact/granular/contact_model.hpp"
#include "mimpact/granular/impact_runs.hpp"
#include "mimpact/granular/run_limits.hpp"

// How far the LZB impact's frozen configuration is from the beads as they move (docs/model.md,
// section 17; docs/design/moving_geometry.md): an LZB run of beads is compared with the compliant
// contacts in the moving geometry, integrated from the same start to the end of its last impact, so
// that the user learns which model the scene requires. The two parts of that distance (the gaps,
// the same share at every speed, and the normals, growing as V^0.8) are the model's, not the
// integrators': no estimate from the LZB run alone gives the first, so it is measured.
namespace mimpact::granular {

// The scene's "configuration_check".
struct ConfigurationCheckSpec {
  bool enabled = true;
  // the moving geometry's tolerance; default: the accuracy / 100, within [1e-10, 1e-4]
  std::optional<double> tolerance;
  // the velocity difference, relative to the fastest body before the impact, above which the
  // run warns; default: the adaptive LZB's tolerance, or 1e-3 for the impulse steps
  std::optional<double> accuracy;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("enabled", self.enabled);
    field("tolerance", self.tolerance, within(1e-12, 1e-4, {}, false, false));
    field("accuracy", self.accuracy, positive("a share of the fastest speed before the impact"));
  }
};

struct ConfigurationCheck {
  double time = 0.0;       // s: the end of the last LZB impact, where the two are compared
  double tolerance = 0.0;  // of the moving geometry's integration
  double accuracy = 0.0;   // the share of the speed above which the run warns
  double speed = 0.0;      // m/s: the fastest body before the impact
  // the bodies' velocities, LZB against the moving geometry, relative to `speed`: the root mean
  // square over the bodies, and the worst body
  double rms_error = 0.0, worst_error = 0.0;
  Eigen::Index worst_body = 0;
  double wall_time = 0.0;  // s, of the moving geometry's run
  // why the moving geometry could not be run (its error), or empty: the check was made
  std::string not_made;

  bool holds() const { return not_made.empty() && worst_error <= accuracy; }
  // One line for the user: the distance, and what to do when it exceeds the accuracy.
  std::string describe() const;
};

// Integrates `model` (whose beads it needs) in the moving geometry to the end of `lzb`'s last
// impact and compares the bodies' velocities there with `lzb`'s. `default_accuracy` is used
// when spec.accuracy is absent. When the moving geometry cannot run (overlaps below double
// precision at the beads' coordinates, its step budget spent), the check says why in
// `not_made` and the LZB run stands.
ConfigurationCheck check_configuration(const ContactModel& model, const ImpactOutcome& lzb,
                                       const ConfigurationCheckSpec& spec, double default_accuracy,
                                       const RunLimits& limits, ProgressMeter* progress = nullptr);

}  // namespace mimpact::granular
