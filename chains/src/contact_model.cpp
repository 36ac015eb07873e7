#include "mimpact/chains/contact_model.hpp"

#include <algorithm>
#include <cmath>

namespace mimpact::chains {

double kinetic_energy(const ContactModel& model, const Eigen::VectorXd& velocity) {
  return 0.5 * model.mass.dot(velocity.cwiseAbs2());
}

double impact_overlap(const ContactModel& model) {
  double smallest = INFINITY;
  for (Eigen::Index j = 0; j < model.contact_count(); ++j) {
    const double u = model.u_minus(j);
    if (!(u < 0.0)) continue;
    const numerics::ContactLaw& law = model.laws[std::size_t(j)];
    const double reduced_mass = 1.0 / model.H.coeff(j, j);
    // the energy of the approach, m u^2 / 2, all stored: K delta^(1+eta) / (1 + eta)
    smallest = std::min(
        smallest, std::pow((1.0 + law.exponent) * reduced_mass * u * u / (2.0 * law.stiffness),
                           1.0 / (1.0 + law.exponent)));
  }
  return smallest;
}

}  // namespace mimpact::chains
