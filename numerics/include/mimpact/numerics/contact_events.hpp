#pragma once

// The events of the compliant integration, classified by a pure function of what a contact's
// gap and rate do over one part of a step: tested on its own
// (tests/numerics/test_contact_events.cpp), used by the compliant integrator and the moving
// geometry to decide which crossings to locate.

namespace mimpact::numerics {

// What ends a segment of the integration at a contact.
// turning: a joined contact's compression ends; reanchoring: an open contact stops separating
// (frozen gaps only)
enum class ContactEvent { none, joining, leaving, turning, reanchoring };

// The overlaps (m) at which a contact joins the integration (-gap reaches `join`) and leaves it
// (-gap falls below `leave`, half of it: the hysteresis keeps a grazing contact from joining
// and leaving at every step).
struct Overlaps {
  double join = 0.0, leave = 0.0;
};

// A watched contact over [t0, t1]: its gap (m) and rate (m/s) at both ends.
struct ContactWatch {
  bool joined = false;
  // open with a gap the frozen-gaps option forgets where it stops separating (closed at some
  // time before, frozen_gaps on)
  bool may_freeze = false;
  double gap_before = 0.0, gap_after = 0.0;
  double rate_before = 0.0, rate_after = 0.0;
};

struct Classified {
  ContactEvent kind = ContactEvent::none;
  // already past its threshold at t0 (crossed at the time of the event just handled, within
  // its tolerance: a symmetric strike moves mirror contacts alike): it happens at t0
  bool at_start = false;
};

// Which event, if any, contact `c` crosses in [t0, t1]. Leaving is tested before turning: a
// contact that both turns and opens within the interval leaves.
constexpr Classified classify(const ContactWatch& c, const Overlaps& overlaps) {
  const double g0 = c.gap_before, g1 = c.gap_after;
  // gaps below the overlap resolution are round-off of the last freeze
  const bool freezes = c.may_freeze && !c.joined && g0 > overlaps.leave;
  if (freezes && c.rate_before <= 0.0) return {ContactEvent::reanchoring, true};
  if (!c.joined && g0 <= -overlaps.join && c.rate_before < 0.0)
    return {ContactEvent::joining, true};
  if (c.joined && g0 >= -overlaps.leave && c.rate_before > 0.0)
    return {ContactEvent::leaving, true};
  if (!c.joined && g0 > -overlaps.join && g1 <= -overlaps.join) return {ContactEvent::joining};
  if (c.joined && g0 < -overlaps.leave && g1 >= -overlaps.leave) return {ContactEvent::leaving};
  if (c.joined && g0 < -overlaps.leave && c.rate_before < 0.0 && c.rate_after >= 0.0)
    return {ContactEvent::turning};
  if (freezes && c.rate_before > 0.0 && c.rate_after <= 0.0) return {ContactEvent::reanchoring};
  return {};
}

// The quantity whose crossing from > 0 to <= 0 is the event: what a root finder narrows.
constexpr double event_function(ContactEvent kind, double gap, double rate,
                                const Overlaps& overlaps) {
  switch (kind) {
    case ContactEvent::joining:
      return gap + overlaps.join;
    case ContactEvent::leaving:
      return -gap - overlaps.leave;
    case ContactEvent::reanchoring:
      return rate;
    default:  // turning
      return -rate;
  }
}

}  // namespace mimpact::numerics
