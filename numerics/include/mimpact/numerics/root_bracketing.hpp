#pragma once

#include <boost/math/tools/toms748_solve.hpp>
#include <cstdint>

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

}  // namespace mimpact::numerics
