#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "mimpact/granular/hertz.hpp"
#include "mimpact/numerics/contact_law.hpp"

// Spheres and planes as they are, not frozen: the geometry the compliant contacts integrate in
// (docs/model.md, section 17). A chain or packing gives its bodies' centres, radii and
// stiffnesses here; the gaps and normals follow from the current positions.
namespace mimpact::granular {

// A rigid plane: the beads lie on the side its unit normal points to.
struct Plane {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    // m
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();  // unit
};

// Beads of any dimension (1 to 3: the components beyond it are 0) and the walls they meet.
// The contact law of two beads, or of a bead and a wall, is `shape` with the stiffness of the
// Hertz contact of their radii and materials (hertz.hpp).
struct BeadGeometry {
  int dimension = 2;
  std::vector<Eigen::Vector3d> position;  // m, of the centres at the start
  Eigen::VectorXd radius;                 // m, per body
  Eigen::VectorXd mass;                   // kg, per body
  std::vector<Plane> walls;
  // the law of every contact but its stiffness: model, exponent, restitution
  numerics::ContactLaw shape;
  std::vector<Material> material, wall_material;  // per body, per wall
  // N/m^eta: every contact's stiffness when > 0 (a scene's contact.stiffness), else Hertz's
  double fixed_stiffness = 0.0;
  // the contacts closed at the start, as the contact model numbers them: two bodies, or a body
  // and -1 - wall
  std::vector<std::pair<std::int32_t, std::int32_t>> closed;
  // Coulomb's mu of a contact of two materials where it depends on the pair (a scene's
  // contact.pairs); empty: shape.friction for every contact
  std::function<double(const Material&, const Material&)> friction_between;

  Eigen::Index body_count() const { return radius.size(); }
  double friction(const Material& a, const Material& b) const {
    return friction_between ? friction_between(a, b) : shape.friction;
  }
  // whether any contact rubs: mu > 0 between two of the bodies' materials or a body's and a
  // wall's
  bool rough() const {
    if (!friction_between) return shape.friction > 0.0;
    std::vector<const Material*> kinds;  // one of each name
    for (const Material& m : material)
      if (std::none_of(kinds.begin(), kinds.end(),
                       [&](const Material* k) { return k->name == m.name; }))
        kinds.push_back(&m);
    for (std::size_t i = 0; i < kinds.size(); ++i) {
      for (std::size_t k = i; k < kinds.size(); ++k)
        if (friction(*kinds[i], *kinds[k]) > 0.0) return true;
      for (const Material& wall : wall_material)
        if (friction(*kinds[i], wall) > 0.0) return true;
    }
    return false;
  }
  // the law of bodies i and k, and of body i and wall w: `shape` with their Hertz stiffness and,
  // with friction, Mindlin's tangential stiffness ratio
  numerics::ContactLaw bead_law(Eigen::Index i, Eigen::Index k) const {
    numerics::ContactLaw law = shape;
    law.stiffness = fixed_stiffness > 0.0 ? fixed_stiffness
                                          : hertz_stiffness(radius(i), material[std::size_t(i)],
                                                            radius(k), material[std::size_t(k)]);
    law.friction = friction(material[std::size_t(i)], material[std::size_t(k)]);
    if (law.friction > 0.0)
      law.tangential_stiffness_ratio =
          mindlin_ratio(material[std::size_t(i)], material[std::size_t(k)]);
    return law;
  }
  numerics::ContactLaw wall_law(Eigen::Index i, std::size_t w) const {
    numerics::ContactLaw law = shape;
    law.stiffness =
        fixed_stiffness > 0.0
            ? fixed_stiffness
            : hertz_stiffness_wall(radius(i), material[std::size_t(i)], wall_material[w]);
    law.friction = friction(material[std::size_t(i)], wall_material[w]);
    if (law.friction > 0.0)
      law.tangential_stiffness_ratio = mindlin_ratio(material[std::size_t(i)], wall_material[w]);
    return law;
  }
};

}  // namespace mimpact::granular
