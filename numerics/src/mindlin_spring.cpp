#include "mimpact/numerics/mindlin_spring.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "mimpact/numerics/coulomb_phase.hpp"

namespace mimpact::numerics::mindlin {

namespace {

// d = xi/|xi|, or s/|s| for a spring with no stretch (a slip just born on a cap of radius 0)
void direction(const double* xi, const double* slip, int rows, double* d) {
  const double* along = coulomb::norm(xi, rows) > 0.0 ? xi : slip;
  const double size = coulomb::norm(along, rows);
  for (int k = 0; k < rows; ++k) d[k] = size > 0.0 ? along[k] / size : 0.0;
}

}  // namespace

Terms terms(double ratio, double exponent, double mu, double normal_force, double delta,
            double delta_rate) {
  if (!(delta > 0.0)) return {.cap_rate = mu / (ratio * exponent) * delta_rate};
  return {.stiffness = ratio * exponent * normal_force / delta,
          .limit = mu * normal_force,
          .cap_rate = mu / (ratio * exponent) * delta_rate};
}

void Spring::start(double* xi, const double* slip, int rows, const Terms& terms) {
  if (mode != Mode::touch) return;
  const double speed = coulomb::norm(slip, rows);
  mode = speed > terms.cap_rate ? Mode::slip : Mode::stick;
  // the stretch since the touch, delta / delta' = r_c / r_c' ago, capped
  const double along = std::max(speed, terms.cap_rate);
  for (int k = 0; k < rows; ++k) xi[k] = along > 0.0 ? terms.cap() * slip[k] / along : 0.0;
}

void Spring::rates(const double* xi, const double* slip, int rows, const Terms& terms,
                   double* force, double* xi_rate) const {
  if (mode != Mode::slip) {
    for (int k = 0; k < rows; ++k) {
      force[k] = -terms.stiffness * xi[k];
      xi_rate[k] = slip[k];
    }
    return;
  }
  double d[2];
  direction(xi, slip, rows, d);
  double along = 0.0;
  for (int k = 0; k < rows; ++k) along += d[k] * slip[k];
  for (int k = 0; k < rows; ++k) {
    force[k] = -terms.limit * d[k];
    xi_rate[k] = slip[k] - along * d[k] + terms.cap_rate * d[k];
  }
}

double Spring::watched(const double* xi, const double* slip, int rows, const Terms& terms) const {
  if (mode != Mode::slip)
    return terms.limit * (1.0 + 16.0 * DBL_EPSILON) - terms.stiffness * coulomb::norm(xi, rows);
  double d[2];
  direction(xi, slip, rows, d);
  double along = 0.0;
  for (int k = 0; k < rows; ++k) along += d[k] * slip[k];
  return along - terms.cap_rate;
}

ByState rates_by_state(const double* xi, const double* slip, int rows, const Terms& terms,
                       double* force, double* xi_rate) {
  double d[3] = {0.0, 0.0, 0.0}, size = 0.0, along = 0.0;
  for (int k = 0; k < rows; ++k) size += xi[k] * xi[k];
  size = std::sqrt(size);
  const double* toward = size > 0.0 ? xi : slip;
  double length = 0.0;
  for (int k = 0; k < rows; ++k) length += toward[k] * toward[k];
  length = std::sqrt(length);
  for (int k = 0; k < rows; ++k) {
    d[k] = length > 0.0 ? toward[k] / length : 0.0;
    along += d[k] * slip[k];
  }
  const double elastic = terms.stiffness * size;
  const bool slipping = elastic >= (1.0 - terms.cap_band) * terms.limit && along > terms.cap_rate;
  const double magnitude = std::min(elastic, terms.limit);
  for (int k = 0; k < rows; ++k) {
    force[k] = -magnitude * d[k];
    xi_rate[k] = slipping ? slip[k] - along * d[k] + terms.cap_rate * d[k] : slip[k];
  }
  if (slipping) return ByState::slipping;
  return elastic >= terms.limit ? ByState::on_cap : ByState::under_cap;
}

ByState rates_by_state(double xi, double slip, const Terms& terms, double& force, double& xi_rate) {
  const double toward = xi != 0.0 ? xi : slip;
  const double d = toward > 0.0 ? 1.0 : toward < 0.0 ? -1.0 : 0.0;
  const double elastic = terms.stiffness * std::abs(xi);
  const bool slipping =
      elastic >= (1.0 - terms.cap_band) * terms.limit && d * slip > terms.cap_rate;
  force = -std::min(elastic, terms.limit) * d;
  xi_rate = slipping ? terms.cap_rate * d : slip;
  if (slipping) return ByState::slipping;
  return elastic >= terms.limit ? ByState::on_cap : ByState::under_cap;
}

void Spring::pass(double* xi, int rows, const Terms& terms) {
  if (mode != Mode::slip) {
    mode = Mode::slip;
    return;
  }
  mode = Mode::stick;
  double d[2];
  const double none[2] = {0.0, 0.0};
  direction(xi, none, rows, d);
  for (int k = 0; k < rows; ++k) xi[k] = terms.cap() * d[k];
}

}  // namespace mimpact::numerics::mindlin
