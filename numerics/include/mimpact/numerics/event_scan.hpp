#pragma once

#include <algorithm>
#include <utility>
#include <vector>

namespace mimpact::numerics {

// An event found on a motion: which watched quantity crossed (an index of the caller's), of
// what kind (the caller's code), and when.
struct Crossing {
  long index = -1;
  int kind = 0;
  double time = 0.0;
};

// Where scan_events searches: [start, end] (s) cut into `samples` equal parts; crossings within
// `tolerance` (s) of the earliest are the same event.
struct ScanInterval {
  double start = 0.0, end = 0.0;
  int samples = 1;
  double tolerance = 0.0;
};

// The events of a motion known at every time of [a, b] = [interval.start, interval.end] (a
// dense output, or a motion in closed form), found as the event-driven and compliant
// integrators find theirs: the interval is cut into `samples` equal parts, the watched quantities
// are evaluated at each cut, and each part is handed to `locate`, which narrows the crossings it
// sees there (TOMS 748) and appends them. The search stops at the first part with a crossing, and
// returns the crossings of that part that lie within `tolerance` of the earliest, in the order
// `locate` appended them. `watch(t, values)` evaluates the quantities at t into `values` (a
// caller's type, two of which the scan keeps and swaps); `locate(t0, t1, at_t0, at_t1, found)`.
template <class Values, class Watch, class Locate>
std::vector<Crossing> scan_events(const ScanInterval& interval, Values& previous, Values& next,
                                  Watch&& watch, Locate&& locate) {
  const double a = interval.start, b = interval.end, tolerance = interval.tolerance;
  const int samples = interval.samples;
  std::vector<Crossing> found;
  watch(a, previous);
  double t_previous = a;
  for (int k = 1; k <= samples; ++k) {
    const double t = k == samples ? b : a + (b - a) * double(k) / double(samples);
    watch(t, next);
    locate(t_previous, t, previous, next, found);
    if (!found.empty()) {
      double earliest = found.front().time;
      for (const Crossing& crossing : found) earliest = std::min(earliest, crossing.time);
      std::erase_if(found,
                    [&](const Crossing& crossing) { return crossing.time > earliest + tolerance; });
      return found;
    }
    std::swap(previous, next);
    t_previous = t;
  }
  return found;
}

}  // namespace mimpact::numerics
