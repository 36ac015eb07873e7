#pragma once

#include <array>
#include <cmath>
#include <string_view>
#include <utility>

#include "mimpact/common/fields.hpp"

namespace mimpact::numerics {

// How a contact gives back its potential energy in expansion (docs/model.md, section 3).
enum class ComplianceModel {
  bi_stiffness,    // stiffer unloading: dE = -(1/e^2) u dP, clamped at 0
  mono_stiffness,  // same curve back, energy dropped once e^2 of the compression work is out
};

constexpr auto enum_names(ComplianceModel) {
  using Name = std::pair<ComplianceModel, std::string_view>;
  return std::array{Name{ComplianceModel::bi_stiffness, "bi-stiffness"},
                    Name{ComplianceModel::mono_stiffness, "mono-stiffness"}};
}

// The compliance and restitution of one contact: F = K delta^eta while loading, with the
// energetic restitution coefficient e of Stronge (e^2 = -W_expansion / W_compression).
struct ContactLaw {
  double stiffness = 0.0;    // K > 0, in N / m^eta
  double exponent = 1.5;     // eta > 0: 1 a linear spring, 3/2 Hertz
  double restitution = 1.0;  // e in [0, 1]
  ComplianceModel model = ComplianceModel::bi_stiffness;
  // mu >= 0, Coulomb's coefficient of a contact with tangential rows (TangentialRows; in the
  // kernel, a relation with tangent rows); 0: frictionless. Read by the integrators that
  // integrate friction (ImpactIntegrator::integrates_friction).
  double friction = 0.0;
  // lambda >= 0, a contact with friction's tangential stiffness over its normal one,
  // k_t = lambda dF/d delta: a Mindlin spring (numerics::mindlin::Spring; for Hertz, lambda =
  // 4 G*/E*, 2 (1 - nu) / (2 - nu) for one material, gives k_t = 8 G* a). 0: a rigid tangential
  // response, Coulomb's law alone, as the LZB impact has it. Read by the compliant integrator.
  double tangential_stiffness_ratio = 0.0;

  bool operator==(const ContactLaw&) const = default;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("stiffness", self.stiffness, positive("N/m^eta").with_symbol("K"));
    field("exponent", self.exponent, positive().with_symbol("eta"));
    field("restitution", self.restitution,
          within(0.0, 1.0).described("0 <= e <= 1").with_symbol("e"));
    field("model", self.model);
    field("friction", self.friction,
          at_least(0.0, "Coulomb's coefficient; 0 frictionless").with_symbol("mu"));
    field("tangential_stiffness_ratio", self.tangential_stiffness_ratio,
          at_least(0.0, "k_t / (dF/d delta); 0 rigid tangentially").with_symbol("lambda"));
  }

  // Below this restitution the energy a contact gives back, e^2 of its compression work, is
  // under half an ulp of that work (e^2 < 2^-54): the integrators release it at once, exactly
  // as for e = 0. Integrating the give-back would take steps e^2 times shorter: below e = 1e-154
  // 1/e^2 overflows, above it the impact does not end in any reasonable time.
  static constexpr double kNegligibleRestitution = 0x1p-27;
  // e as the integrators use it: 0 below kNegligibleRestitution.
  double effective_restitution() const {
    return restitution < kNegligibleRestitution ? 0.0 : restitution;
  }

  // c(eta) K^(1/(1+eta)): the force for a potential energy E is this times E^(eta/(1+eta)),
  // the law F = K delta^eta rewritten with E = K delta^(1+eta) / (1+eta).
  double force_coefficient() const;
  double force_from_energy(double energy) const;
  // K delta^eta, the loading force at indentation delta >= 0 (m).
  double force(double delta) const;
};

// x^exponent for x >= 0, with the linear and Hertz exponents (1 and 3/2) by a product and a
// square root: the force laws are evaluated at every stage of the integrators, and std::pow
// is several times dearer than sqrt.
inline double power_law(double x, double exponent) {
  if (exponent == 1.5) return x * std::sqrt(x);
  if (exponent == 1.0) return x;
  return std::pow(x, exponent);
}

// K delta^(3/2), Hertz's force (N) at overlap delta >= 0 (m) for a stiffness K (N / m^(3/2)):
// the one expression every elastic Hertz contact is evaluated by, to its last bit.
inline double hertz_force(double stiffness, double delta) {
  return stiffness * (delta * std::sqrt(delta));
}

inline double ContactLaw::force(double delta) const {
  return stiffness * power_law(delta, exponent);
}

// The force (N) of a compliant contact at overlap delta (m) whose largest overlap since it
// closed is delta_max: K delta^eta on loading (delta >= delta_max), and for e < 1 the stiffer
// unloading and reloading curve F_M ((delta - delta_r) / (delta_max - delta_r))^eta, with
// delta_r = delta_max (1 - e^2) and F_M = K delta_max^eta (docs/model.md, section 3): the
// compliant model the LZB impact reparametrizes, integrated in time.
inline double hysteresis_force(const ContactLaw& law, double delta, double delta_max) {
  if (!(delta > 0.0)) return 0.0;
  if (delta >= delta_max || law.restitution >= 1.0) return law.force(delta);
  const double e = law.restitution;
  const double delta_r = delta_max * (1.0 - e * e);
  if (delta <= delta_r) return 0.0;
  return law.force(delta_max) * power_law((delta - delta_r) / (delta_max - delta_r), law.exponent);
}

// Its potential energy (J) there, on the curve it is on.
inline double hysteresis_energy(const ContactLaw& law, double delta, double delta_max) {
  if (!(delta > 0.0)) return 0.0;
  if (delta >= delta_max || law.restitution >= 1.0)
    return law.force(delta) * delta / (1.0 + law.exponent);
  const double delta_r = delta_max * (1.0 - law.restitution * law.restitution);
  if (delta <= delta_r) return 0.0;
  return hysteresis_force(law, delta, delta_max) * (delta - delta_r) / (1.0 + law.exponent);
}

}  // namespace mimpact::numerics
