#include "impulse_step_rules.hpp"

#include <algorithm>

namespace mimpact::numerics::detail {

// Written with the known F(e0) so only expm1 and log1p are needed.
double step_duration(double delta_p, double e0, double e1, double force, double coefficient,
                     double power) {
  if (e0 <= 0.0) {  // the contact was entering compression: E grows from 0 to e1
    if (e1 <= 0.0) return delta_p / force;  // unresolved: the paper's rule
    return delta_p / ((1.0 - power) * coefficient * std::pow(e1, power));
  }
  double length = delta_p;
  if (e1 < 0.0) {  // E reaches 0 inside the step; the rest of it carries no force
    length = std::isinf(e1) ? 0.0 : delta_p * e0 / (e0 - e1);
    e1 = 0.0;
  }
  const double r = (e1 - e0) / e0;
  const double q = 1.0 - power;
  const double factor = std::abs(r) < 1e-12 ? 1.0 : std::expm1(q * std::log1p(r)) / (q * r);
  return length / force * factor;
}

}  // namespace mimpact::numerics::detail
