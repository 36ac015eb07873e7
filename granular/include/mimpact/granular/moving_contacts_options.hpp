#pragma once

#include <cstdint>
#include <limits>

#include "mimpact/common/fields.hpp"
#include "mimpact/numerics/ode_options.hpp"

namespace mimpact::granular {

// The options of the compliant contacts in the moving geometry (moving_contacts.hpp).
struct MovingContactsOptions {
  // the integration of each group: Runge-Kutta-Nystrom 4(3) to these tolerances (positions to
  // absolute_tolerance m, velocities to absolute_tolerance / T m/s and impulses to
  // absolute_tolerance m / T N s, with T the quickest contact's overlap over its closing speed
  // and m the lightest mass), events to event_tolerance s
  numerics::OdeOptions ode{.absolute_tolerance = 1e-17,
                           .relative_tolerance = 1e-10,
                           .event_tolerance = 1e-13,
                           .samples_per_step = 4};
  // m: a contact carries force once its overlap exceeds this, and until it falls below half of
  // it (a grazing contact does not join and leave at every step)
  double overlap_resolution = 1e-12;
  // m: the neighbour lists' skin; 0: a fifth of the smallest radius
  double skin = 0.0;
  // time steps of all groups and windows (every loop of the run), before it is abandoned
  std::int64_t max_steps = 10'000'000;
  // the bodies those steps carried, summed: a caller's budget of work (the configuration check's)
  std::int64_t max_body_steps = std::numeric_limits<std::int64_t>::max();

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    numerics::OdeOptions::visit_fields(self.ode, field);
    field("overlap_resolution", self.overlap_resolution, positive("m"));
    field("skin", self.skin, at_least(0.0, "m, 0 for a fifth of the smallest radius"));
    field("max_steps", self.max_steps, at_least(1));
  }
};

}  // namespace mimpact::granular
