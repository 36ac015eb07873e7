#pragma once

#include <cstdint>

#include "mimpact/common/fields.hpp"

namespace mimpact::numerics {

// The options of the adaptive LZB integrator (lzb_adaptive_integrator.hpp).
struct LzbAdaptiveOptions {
  // below 1e-13 double precision cannot meet the tolerance
  static constexpr Allowed kToleranceRange =
      within(1e-13, 0.1)
          .described("1e-13 <= tolerance <= 0.1 (below 1e-13 double precision cannot meet it)");

  // The relative accuracy asked of the result. With V the fastest pre-impact approach,
  // |u-|max, the velocities are to be right to tolerance * V, and each contact's impulse and
  // indentation to the same fraction of its natural ones (V / H_jj, and the indentation that
  // stores V^2 / (2 H_jj)); each step's local error is held to a share of that, so that the
  // steps' errors add up to about the tolerance. A contact joins the impact once it approaches
  // faster than tolerance * V, and the impact ends when no contact approaches faster and none holds
  // more than (tolerance * V)^2 / (2 H_jj): the same rule as the impulse steps' with
  // tolerance * V in place of a fraction of H_jj delta_p.
  double tolerance = 1e-8;
  // The impact is abandoned (status step_limit) after this many steps and restarts.
  std::int64_t max_steps = 100'000'000;
  // Or after this many located events (contacts closing, opening or switching, each a restart)
  // per contact of the impact, and at least kLeastEvents: bodies that rattle between others
  // without their events thinning out (six beads of radius 1e-12 m between a 5 mm striker and a
  // wall, 200 000 events a second; an HCP packing at e = 0.07 with friction, 28 000) end there,
  // an event costing about 0.5 us per contact. Ordinary impacts take up to 50 events a contact;
  // a 100-bead chain struck against a wall at e = 0.9 takes 2 500, and needs the field raised
  // (docs/limits.md).
  std::int64_t events_per_contact = 1'000;
  static constexpr std::int64_t kLeastEvents = 100'000;
  // The observer sees the state every this long (s) of the impact; 0: the start and the end.
  double sample_interval = 0.0;
  // An impact whose laws are continuous at its switches (e = 1, or bi-stiffness with e > 0)
  // keeps them within its steps while at least this many contacts hold energy or approach, until
  // fewer than half as many do; otherwise each switch is located and ends a step of all the
  // contacts, whose switches grow with them (a packing's impact then costs as the square of its
  // contacts). Kept within, a switch costs nothing of its own, and the steps are those the
  // released forces' error allows: the cheaper where many contacts switch, the dearer where few
  // do (docs/design/adaptive_lzb.md: on hexagonal packings locating is the cheaper below about
  // 128). 1: always within the steps; more than the impact's contacts: always located.
  std::int64_t within_steps_from = 128;
  // Contacts the observer sees (empty: all of them), until set_sampled_contacts changes them.
  std::vector<Eigen::Index> sampled_contacts;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("tolerance", self.tolerance, kToleranceRange);
    field("max_steps", self.max_steps, at_least(1));
    field("events_per_contact", self.events_per_contact, at_least(1));
    field("sample_interval", self.sample_interval, at_least(0.0, "s, 0: start and end only"));
    field("within_steps_from", self.within_steps_from, at_least(1, "contacts"));
    field("sampled_contacts", self.sampled_contacts, at_least(0, "contact indices"));
  }
};

}  // namespace mimpact::numerics
