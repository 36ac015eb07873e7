#include "mimpact/numerics/contact_law.hpp"

#include <cmath>

#include "mimpact/common/error.hpp"

namespace mimpact::numerics {

double ContactLaw::force_coefficient() const {
  return std::pow(1.0 + exponent, exponent / (1.0 + exponent)) *
         std::pow(stiffness, 1.0 / (1.0 + exponent));
}

double ContactLaw::force_from_energy(double energy) const {
  return force_coefficient() * std::pow(energy, exponent / (1.0 + exponent));
}

}  // namespace mimpact::numerics
