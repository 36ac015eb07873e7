#pragma once

#include "mimpact/common/fields.hpp"

namespace mimpact::numerics {

// Error control and event location of an ODE integrated with dense output (Dormand-Prince
// 5(4)): the smooth motion of the event-driven and compliant integrators. Events are searched
// at samples_per_step interior samples of every step and placed to event_tolerance. Between two
// samples a gap may turn once (a dip below 0 and back is found through its rate), and a step
// held to these tolerances is short against any oscillation: four samples find the events
// that eight did in every test, in two thirds of the time.
struct OdeOptions {
  double absolute_tolerance = 1e-10;  // error control (the state's units)
  double relative_tolerance = 1e-10;
  double max_step = 0.0;           // s, the largest step; 0 for no limit
  double event_tolerance = 1e-10;  // s: an event is placed at most this long after it happens
  int samples_per_step = 4;        // interior samples of each step searched for events

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("absolute_tolerance", self.absolute_tolerance, positive("the state's units"));
    field("relative_tolerance", self.relative_tolerance, positive());
    field("max_step", self.max_step, at_least(0.0, "s, 0 for no limit"));
    field("event_tolerance", self.event_tolerance, positive("s"));
    field("samples_per_step", self.samples_per_step, within(1, 1e6));
  }
};

}  // namespace mimpact::numerics
