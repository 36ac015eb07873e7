#include "mimpact/granular/hertz.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "mimpact/common/error.hpp"

namespace mimpact::granular {

double bead_mass(double radius, const Material& material) {
  return 4.0 / 3.0 * std::numbers::pi * radius * radius * radius * material.density;
}

double effective_modulus(const Material& a, const Material& b) {
  return 1.0 / ((1.0 - a.poisson * a.poisson) / a.young + (1.0 - b.poisson * b.poisson) / b.young);
}

double hertz_stiffness(double radius_a, const Material& a, double radius_b, const Material& b) {
  const double effective_radius = radius_a * radius_b / (radius_a + radius_b);
  return 4.0 / 3.0 * std::sqrt(effective_radius) * effective_modulus(a, b);
}

void check_stiffness(double stiffness, const std::string& contact, const Material& a,
                     const Material& b) {
  if (stiffness >= std::numeric_limits<double>::min() && std::isfinite(stiffness)) return;
  throw InvalidInput("the contact of " + contact +
                     " has the Hertz stiffness K = " + to_text(stiffness) +
                     " N/m^1.5 from young = " + to_text(a.young) + " and " + to_text(b.young) +
                     " Pa; allowed: Young's moduli and radii that make K = (4/3) sqrt(R*) E* a "
                     "finite normal double (>= 2.2e-308)");
}

double mindlin_ratio(const Material& a, const Material& b) {
  auto compliance = [](const Material& m) {  // (2 - nu) / G
    return (2.0 - m.poisson) * 2.0 * (1.0 + m.poisson) / m.young;
  };
  return 4.0 / (compliance(a) + compliance(b)) / effective_modulus(a, b);
}

double hertz_stiffness_wall(double radius, const Material& bead, const Material& wall) {
  return 4.0 / 3.0 * std::sqrt(radius) * effective_modulus(bead, wall);
}

}  // namespace mimpact::granular
