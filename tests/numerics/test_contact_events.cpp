// The compliant integrator's event classification, on its own: for every kind of event, a
// contact whose gap and rate cross its threshold over an interval is classified so, one already
// past it where the interval starts happens there, and one that crosses nothing is no event;
// the event function is > 0 before the crossing and <= 0 after, the sign convention the root
// finder needs.
#include "mimpact/numerics/contact_events.hpp"

#include <gtest/gtest.h>

namespace mimpact::numerics {
namespace {

constexpr Overlaps kOverlaps{.join = 1e-12, .leave = 0.5e-12};  // m

ContactWatch watch(bool joined, double gap_before, double gap_after, double rate_before,
                   double rate_after, bool may_freeze = false) {
  ContactWatch c;
  c.joined = joined;
  c.may_freeze = may_freeze;
  c.gap_before = gap_before;
  c.gap_after = gap_after;
  c.rate_before = rate_before;
  c.rate_after = rate_after;
  return c;
}

void expect(const ContactWatch& c, ContactEvent kind, bool at_start) {
  const Classified classified = classify(c, kOverlaps);
  EXPECT_EQ(classified.kind, kind);
  EXPECT_EQ(classified.at_start, at_start);
  if (kind == ContactEvent::none || at_start) return;
  // the event function changes sign across the interval: > 0 before, <= 0 after
  EXPECT_GT(event_function(kind, c.gap_before, c.rate_before, kOverlaps), 0.0);
  EXPECT_LE(event_function(kind, c.gap_after, c.rate_after, kOverlaps), 0.0);
}

TEST(ContactEvents, AnOpenContactJoinsWhereItsOverlapReachesTheJoinOverlap) {
  expect(watch(false, 1e-6, -2e-12, -1.0, -1.0), ContactEvent::joining, false);
  // approaching but still short of the join overlap: no event
  expect(watch(false, 1e-6, -0.9e-12, -1.0, -1.0), ContactEvent::none, false);
  // past it already, still approaching (a mirror contact of the event just handled)
  expect(watch(false, -1.5e-12, -3e-12, -1.0, -1.0), ContactEvent::joining, true);
  // past it but separating: it opens, no join
  expect(watch(false, -1.5e-12, 1e-9, 1.0, 1.0), ContactEvent::none, false);
}

TEST(ContactEvents, AJoinedContactLeavesWhereItsOverlapFallsBelowHalfTheJoinOverlap) {
  expect(watch(true, -1e-6, -0.4e-12, 1.0, 1.0), ContactEvent::leaving, false);
  // between the two overlaps: the hysteresis keeps it joined
  expect(watch(true, -1e-6, -0.7e-12, 1.0, 1.0), ContactEvent::none, false);
  expect(watch(true, -0.4e-12, 1e-9, 1.0, 1.0), ContactEvent::leaving, true);
  // opened within the tolerance of the last event but approaching again: it stays
  expect(watch(true, -0.4e-12, -1e-9, -1.0, -1.0), ContactEvent::none, false);
}

TEST(ContactEvents, AJoinedContactTurnsWhereItsCompressionEnds) {
  expect(watch(true, -1e-6, -1.1e-6, -0.1, 0.05), ContactEvent::turning, false);
  // still compressing, or already expanding: no event
  expect(watch(true, -1e-6, -1.1e-6, -0.1, -0.05), ContactEvent::none, false);
  expect(watch(true, -1e-6, -0.9e-6, 0.1, 0.2), ContactEvent::none, false);
  // turned and opened within one interval: it leaves, which takes precedence
  expect(watch(true, -1e-6, 1e-7, -0.1, 0.3), ContactEvent::leaving, false);
}

TEST(ContactEvents, AFrozenGapIsReanchoredWhereTheContactStopsSeparating) {
  expect(watch(false, 1e-6, 1.1e-6, 0.1, -0.02, true), ContactEvent::reanchoring, false);
  // turned by a collision where the interval starts
  expect(watch(false, 1e-6, 0.9e-6, -0.1, -0.1, true), ContactEvent::reanchoring, true);
  // without frozen gaps the same contact only approaches
  expect(watch(false, 1e-6, 1.1e-6, 0.1, -0.02, false), ContactEvent::none, false);
  // a gap within the leave overlap is round-off of the last freeze: it is not frozen again
  expect(watch(false, 0.4e-12, 0.3e-12, -0.1, -0.1, true), ContactEvent::none, false);
  // still separating
  expect(watch(false, 1e-6, 1.1e-6, 0.1, 0.05, true), ContactEvent::none, false);
}

}  // namespace
}  // namespace mimpact::numerics
