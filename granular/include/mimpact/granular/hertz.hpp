#pragma once

#include <string>

#include "mimpact/common/fields.hpp"

namespace mimpact::granular {

// An isotropic elastic material.
struct Material {
  double density = 0.0;  // kg/m^3
  double young = 0.0;    // Young's modulus E (Pa)
  double poisson = 0.0;  // Poisson's ratio nu
  std::string name;      // optional: what a scene's contact.pairs call it

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("name", self.name, any("what contact.pairs call this material"));
    field("density", self.density, positive("kg/m^3").needed());
    field("young", self.young, positive("Pa").needed());
    field("poisson", self.poisson,
          within(-1.0, 0.5, {}, true, true).described("-1 < nu < 0.5").needed());
  }
};

// (4/3) pi R^3 rho.
double bead_mass(double radius, const Material& material);

// E* with 1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2.
double effective_modulus(const Material& a, const Material& b);

// Throws InvalidInput naming `contact` and the materials' Young's moduli unless `stiffness`
// (a Hertz stiffness of materials a and b) is a finite normal double: a subnormal modulus makes
// K = 0, which no impact resolves.
void check_stiffness(double stiffness, const std::string& contact, const Material& a,
                     const Material& b);

// Hertz stiffness K = (4/3) sqrt(R*) E* of two spheres (1/R* = 1/R_1 + 1/R_2), so that
// F = K delta^(3/2) (Johnson, "Contact Mechanics", 1985, section 4.2).
double hertz_stiffness(double radius_a, const Material& a, double radius_b, const Material& b);

// The same for a sphere against a flat rigid wall of the given material (R* = R).
double hertz_stiffness_wall(double radius, const Material& bead, const Material& wall);
// Mindlin's tangential stiffness over Hertz's normal one, k_t / (dF/d delta) = 8 G* a / (2 E* a)
// = 4 G*/E*, with 1/G* = (2 - nu_a)/G_a + (2 - nu_b)/G_b (G = E / (2 (1 + nu))): 2 (1 - nu) /
// (2 - nu) for one material (numerics::ContactLaw::tangential_stiffness_ratio).
double mindlin_ratio(const Material& a, const Material& b);

}  // namespace mimpact::granular
