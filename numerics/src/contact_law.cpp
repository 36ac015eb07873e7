#include "mimpact/numerics/contact_law.hpp"

#include <cmath>

#include "mimpact/numerics/error.hpp"

namespace mimpact::numerics {

std::string_view to_string(ComplianceModel model) {
  return model == ComplianceModel::bi_stiffness ? "bi-stiffness" : "mono-stiffness";
}

std::optional<ComplianceModel> compliance_model_from_string(std::string_view text) {
  if (text == "bi-stiffness") return ComplianceModel::bi_stiffness;
  if (text == "mono-stiffness") return ComplianceModel::mono_stiffness;
  return std::nullopt;
}

void ContactLaw::validate(const std::string& name) const {
  if (!(stiffness > 0.0 && std::isfinite(stiffness)))
    throw InvalidInput(name + ": " + invalid_value_message("stiffness K", stiffness,
                                                           "a finite K > 0 (N/m^eta)"));
  if (!(exponent > 0.0 && std::isfinite(exponent)))
    throw InvalidInput(name + ": " + invalid_value_message("exponent eta", exponent,
                                                           "a finite eta > 0"));
  if (!(restitution >= 0.0 && restitution <= 1.0))
    throw InvalidInput(name + ": " + invalid_value_message("restitution e", restitution,
                                                           "0 <= e <= 1"));
}

double ContactLaw::force_coefficient() const {
  return std::pow(1.0 + exponent, exponent / (1.0 + exponent)) *
         std::pow(stiffness, 1.0 / (1.0 + exponent));
}

double ContactLaw::force_from_energy(double energy) const {
  return force_coefficient() * std::pow(energy, exponent / (1.0 + exponent));
}

}  // namespace mimpact::numerics
