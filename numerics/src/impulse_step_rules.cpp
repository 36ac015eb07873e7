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

double phase_end(const PhaseStep& step) {
  const double u0 = step.u, du = step.du, e0 = step.energy, dp = step.delta_p;
  const double f = step.expansion_rate, level = step.release_level;
  const bool released_at_once = step.drops_at_turn;
  if (u0 < 0.0 && u0 + du > 0.0) {
    const double crossing = -u0 / du;
    if (crossing >= kSmallestCut) return crossing;
  } else if (u0 + 0.5 * du < 0.0) {
    return 1.0;  // compression all along
  }
  // nothing to give back (e = 0, or E already at its level): release where the step's work
  // is zero, at once when u0 >= 0
  if (released_at_once || level >= e0) return std::clamp(-2.0 * u0 / du, 0.0, 1.0);
  const double a = 0.5 * f * dp * du, b = f * dp * u0, c = level - e0;
  if (a + b + c <= 0.0) return 1.0;  // E stays above its release level
  const double discriminant = b * b - 4.0 * a * c;
  const double denominator = -b - std::sqrt(std::max(discriminant, 0.0));
  return denominator < 0.0 ? std::clamp(2.0 * c / denominator, 0.0, 1.0) : 1.0;
}

}  // namespace mimpact::numerics::detail
