#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace mimpact::numerics {

// How a contact gives back its potential energy in expansion (LZB.md section 3).
enum class ComplianceModel {
  bi_stiffness,    // stiffer unloading: dE = -(1/e^2) u dP, clamped at 0
  mono_stiffness,  // same curve back, energy dropped once e^2 of the compression work is out
};

std::string_view to_string(ComplianceModel model);  // "bi-stiffness" | "mono-stiffness"
std::optional<ComplianceModel> compliance_model_from_string(std::string_view text);

// The compliance and restitution of one contact: F = K delta^eta while loading, with the
// energetic restitution coefficient e of Stronge (e^2 = -W_expansion / W_compression).
struct ContactLaw {
  double stiffness = 0.0;    // K > 0, in N / m^eta
  double exponent = 1.5;     // eta > 0: 1 a linear spring, 3/2 Hertz
  double restitution = 1.0;  // e in [0, 1]
  ComplianceModel model = ComplianceModel::bi_stiffness;

  // Throws InvalidInput naming `name` (e.g. "contact 3") and the field that is out of range.
  void validate(const std::string& name) const;

  // c(eta) K^(1/(1+eta)): the force for a potential energy E is this times E^(eta/(1+eta)),
  // the law F = K delta^eta rewritten with E = K delta^(1+eta) / (1+eta).
  double force_coefficient() const;
  double force_from_energy(double energy) const;
};

}  // namespace mimpact::numerics
