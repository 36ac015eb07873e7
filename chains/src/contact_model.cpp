#include "mimpact/chains/contact_model.hpp"

#include <algorithm>
#include <cmath>

#include "mimpact/common/error.hpp"

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

double natural_impulse(const ContactModel& model) {
  double smallest = INFINITY;
  const int d = model.dimension;
  for (Eigen::Index b = 0; b < model.body_count(); ++b) {
    const double speed = model.velocity.segment(b * d, d).norm();
    if (speed != 0.0) smallest = std::min(smallest, model.mass(b * d) * speed);
  }
  return smallest;
}

void check_delta_p(const ContactModel& model, double delta_p, std::int64_t max_steps,
                   const std::string& field) {
  const double impulse = natural_impulse(model);
  if (!(delta_p > 0.0 && delta_p < impulse))
    throw InvalidInput(invalid_value_message(field, delta_p,
                                             "0 < delta_p < the striker's momentum m V = " +
                                                 to_text(impulse) + " N s (best <= 1e-3 m V)"));
  if (impulse / delta_p > double(max_steps))
    throw InvalidInput(
        invalid_value_message(field, delta_p,
                              ">= m V / max_steps = " + to_text(impulse / double(max_steps)) +
                                  " N s: the impact takes at least m V / delta_p impulse steps"));
}

}  // namespace mimpact::chains
