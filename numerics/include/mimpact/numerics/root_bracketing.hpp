#pragma once

#include <boost/math/tools/toms748_solve.hpp>
#include <cfloat>
#include <cstdint>
#include <optional>

namespace mimpact::numerics {

// An interval around a crossing: f(lower) > 0 >= f(upper).
struct Bracket {
  double lower;
  double upper;
};

// Narrows a bracket of a continuous f, f(lower) > 0 >= f(upper), until it is at most
// `tolerance` wide, with the method of Alefeld, Potra and Shi (ACM TOMS 748, 1995) of
// Boost.Math. The upper end is where f has crossed: an event placed there lies at most
// `tolerance` after the true crossing.
template <class Function>
Bracket narrow_crossing(Function&& f, double lower, double upper, double f_lower, double f_upper,
                        double tolerance) {
  if (f_upper == 0.0 || upper - lower <= tolerance) return {lower, upper};
  std::uintmax_t iterations = 200;
  const auto narrow_enough = [tolerance](double a, double b) { return b - a <= tolerance; };
  const auto [a, b] = boost::math::tools::toms748_solve(f, lower, upper, f_lower, f_upper,
                                                        narrow_enough, iterations);
  // toms748 may stop on an exact zero at either end; keep f(upper) <= 0
  return f(b) <= 0.0 ? Bracket{a, b} : Bracket{b, b};
}

// Where a watched value (> 0 before its switch, <= 0 once it happened) crossed 0 in the step
// [t0, t1] of a segment begun at segment_start, from its values q0 and q1 at the ends: none if
// it did not (or did before this step), t0 if it was past already when the segment began
// (rounding), else narrowed by TOMS 748 on value_at(t) to a few ulp of t.
template <class Value>
std::optional<double> crossing_time(double q0, double q1, double t0, double t1,
                                    double segment_start, Value&& value_at) {
  if (q1 > 0.0 || (q0 <= 0.0 && t0 != segment_start)) return std::nullopt;
  if (!(q0 > 0.0)) return t0;
  return narrow_crossing(value_at, t0, t1, q0, q1, 4.0 * DBL_EPSILON * t1).upper;
}

}  // namespace mimpact::numerics
