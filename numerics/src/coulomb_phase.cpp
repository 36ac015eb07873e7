#include "mimpact/numerics/coulomb_phase.hpp"

#include <cmath>
#include <limits>

namespace mimpact::numerics::coulomb {

double norm(const double* v, int rows) {
  return rows == 1 ? std::abs(v[0]) : std::hypot(v[0], v[1]);
}

void Phase::start(const double* slip, int rows, double tolerance) {
  mode = norm(slip, rows) > tolerance ? Mode::slip : Mode::stick;
  live = mode == Mode::slip && rows == 2;
  from_rest = false;
  if (mode == Mode::slip && rows == 1) direction = {slip[0] > 0.0 ? 1.0 : -1.0, 0.0};
}

double Phase::excess(const double* x, int rows, double limit) const {
  return forced ? std::numeric_limits<double>::infinity() : norm(x, rows) - limit;
}

void Phase::slip_against(const double* x, int rows) {
  const double size = norm(x, rows);
  mode = Mode::slip;
  live = forced = false;
  from_rest = true;
  for (int k = 0; k < rows; ++k) direction[std::size_t(k)] = size > 0.0 ? -x[k] / size : 0.0;
}

void Phase::slip_force(double limit, const double* slip, int rows, double* force) const {
  const double speed = live ? norm(slip, rows) : 1.0;
  for (int k = 0; k < rows; ++k)
    force[k] =
        live ? (speed > 0.0 ? -limit * slip[k] / speed : 0.0) : -limit * direction[std::size_t(k)];
}

std::array<double, 2> Phase::watched(double limit, const double* slip, const double* force,
                                     int rows, double tolerance) const {
  const double speed = norm(slip, rows);
  if (mode == Mode::stick) {  // no force either way (a contact at rest or opening) ends nothing
    const double size = norm(force, rows);
    return {limit > 0.0 || size > 0.0 ? limit - size : 1.0, 1.0};
  }
  if (live) return {speed - tolerance, 1.0};
  double along = 0.0;
  for (int k = 0; k < rows; ++k) along += slip[k] * direction[std::size_t(k)];
  if (from_rest) return {along + tolerance, 2.0 * tolerance - speed};
  return {along, 1.0};
}

}  // namespace mimpact::numerics::coulomb
