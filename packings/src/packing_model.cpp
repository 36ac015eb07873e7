#include "mimpact/packings/packing_model.hpp"

#include <algorithm>
#include <cmath>

#include "mimpact/common/error.hpp"
#include "mimpact/granular/cell_grid.hpp"
#include "mimpact/granular/run_limits.hpp"
#include "mimpact/kernel/json_document.hpp"
#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/linear_relation.hpp"
#include "mimpact/numerics/delassus.hpp"
#include "mimpact/plugins/lzb_law.hpp"
#include "packing_beads.hpp"

namespace mimpact::packings {

namespace {

// a centre in three dimensions whatever the packing's (a planar packing's third coordinate is 0)
Eigen::Vector3d point_of(const Vector& centre) {
  Eigen::Vector3d at = Eigen::Vector3d::Zero();
  at.head(centre.size()) = centre;
  return at;
}

std::string bead_name(const PackingModel& model, Eigen::Index body) {
  if (body >= model.bead_count) return "striker " + std::to_string(body - model.bead_count);
  if (model.columns == 0) return "bead " + std::to_string(body);
  const Eigen::Index row = body / model.columns;
  const std::string layer =
      model.layers > 0 ? "layer " + std::to_string(row / model.rows) + ", " : std::string();
  return "bead " + std::to_string(body) + " (" + layer + "row " +
         std::to_string(model.layers > 0 ? row % model.rows : row) + ", column " +
         std::to_string(body % model.columns) + ")";
}

// The beads by their centres, in cells as wide as two of the largest touch.
granular::CellGrid index_of(const std::vector<Body>& bodies, double largest_radius, int dimension) {
  granular::CellGrid grid(2.0 * largest_radius * (1.0 + kTouching), dimension);
  for (std::size_t i = 0; i < bodies.size(); ++i)
    grid.insert(std::int32_t(i), point_of(bodies[i].centre));
  return grid;
}

// Calls visit(j) for every body j of `grid` whose centre may lie within `reach` of `centre`, by
// increasing j.
template <class Visit>
void near(const granular::CellGrid& grid, const Vector& centre, double reach, Visit&& visit) {
  std::vector<Eigen::Index> found;
  grid.visit_near(point_of(centre), reach, [&](std::int32_t j) { found.push_back(j); });
  std::sort(found.begin(), found.end());
  for (Eigen::Index j : found) visit(j);
}

class PackingBuilder {
 public:
  PackingBuilder(const PackingScene& scene, PackingModel& model, const granular::RunLimits& limits)
      : scene_(scene), model_(model), limits_(limits) {}

  void build() {
    if (scene_.lattice) {
      const LatticeSpec& lattice = *scene_.lattice;
      const int layers = std::max(lattice.layers, 1);
      granular::check_memory(double(layers) * double(lattice.rows) * double(lattice.columns) *
                                 bead_bytes(lattice_dimension(lattice.type)),
                             "lattice (" + std::to_string(layers) + " x " +
                                 std::to_string(lattice.rows) + " x " +
                                 std::to_string(lattice.columns) + " beads)",
                             limits_);
    }
    bodies_ = scene_.lattice ? lattice_beads(*scene_.lattice)
                             : listed_beads(*scene_.beads, scene_.directory, limits_);
    model_.dimension = int(bodies_.front().centre.size());
    check_dimension(scene_, model_.dimension);
    model_.bead_count = Eigen::Index(bodies_.size());
    if (scene_.lattice) {
      model_.layers = scene_.lattice->layers;
      model_.rows = scene_.lattice->rows;
      model_.columns = scene_.lattice->columns;
    }
    for (const Body& body : bodies_) largest_radius_ = std::max(largest_radius_, body.radius);
    const granular::CellGrid beads = index_of(bodies_, largest_radius_, model_.dimension);
    find_bead_contacts(beads);
    place_walls();
    place_strikers(beads);
    assemble();
  }

 private:
  // the contact of materials a and b: Hertz's stiffness and their pair's friction
  void add_contact(PackingContact contact, double hertz_stiffness, const granular::Material& a,
                   const granular::Material& b) {
    model_.contacts.push_back(contact);
    model_.laws.push_back(scene_.contact.law(hertz_stiffness));
    model_.laws.back().friction = scene_.contact.friction_of(a, b);
  }

  // "FILE lines M and N: " where two beads come from a bead list, as its other messages
  std::string where_listed(const Body& a, const Body& b) const {
    if (a.line == 0 || b.line == 0) return "";
    return bead_file(*scene_.beads, scene_.directory).string() + " lines " +
           std::to_string(a.line) + " and " + std::to_string(b.line) + ": ";
  }

  // Two bodies touch within kTouching of their radii: a contact at the distance of their
  // centres; closer, they overlap.
  void touch(Eigen::Index i, Eigen::Index j, const Vector& centre_i) {
    const Body& a = bodies_[std::size_t(i)];
    const Body& b = bodies_[std::size_t(j)];
    const Vector between = b.centre - centre_i;
    const double distance = between.norm(), reach = a.radius + b.radius;
    if (distance > reach * (1.0 + kTouching)) return;
    if (distance < reach * (1.0 - kTouching))
      throw InvalidInput(where_listed(a, b) + bead_name(model_, i) + " and " +
                         bead_name(model_, j) + " overlap by " + to_text(reach - distance) +
                         " m (" + to_text(1.0 - distance / reach) +
                         " of the sum of their radii); allowed: touching within " +
                         to_text(kTouching) + " of it, or apart");
    add_contact({.first = i, .second = j, .normal = between / distance, .rest = distance},
                granular::hertz_stiffness(a.radius, a.material, b.radius, b.material), a.material,
                b.material);
  }

  // contacts by their first, then second bead
  void find_bead_contacts(const granular::CellGrid& beads) {
    for (Eigen::Index i = 0; i < model_.bead_count; ++i) {
      const Body& bead = bodies_[std::size_t(i)];
      near(beads, bead.centre, (bead.radius + largest_radius_) * (1.0 + kTouching),
           [&](Eigen::Index j) {
             if (j > i) touch(i, j, bead.centre);
           });
    }
  }

  // the line of a wall given by its side: touching the outermost beads
  void wall_line(const WallSpec& wall, Vector& point, Vector& normal) const {
    if (!wall.side) {
      point = vector_of(wall.point);
      normal = vector_of(wall.normal).normalized();
      return;
    }
    static const double kNormals[][3] = {{0, 1, 0},  {0, -1, 0}, {1, 0, 0},
                                         {-1, 0, 0}, {0, 0, 1},  {0, 0, -1}};
    const double* n = kNormals[int(*wall.side)];
    normal = vector_of({n[0], n[1], n[2]}, model_.dimension);
    // the plane lies where the beads reach furthest against the normal
    double reach = INFINITY;
    for (Eigen::Index i = 0; i < model_.bead_count; ++i)
      reach = std::min(reach,
                       normal.dot(bodies_[std::size_t(i)].centre) - bodies_[std::size_t(i)].radius);
    point = reach * normal;
  }

  void place_walls() {
    for (std::size_t w = 0; w < scene_.walls.size(); ++w) {
      Vector point, normal;
      wall_line(scene_.walls[w], point, normal);
      model_.wall_points.push_back(point);
      model_.wall_normals.push_back(normal);
      for (Eigen::Index i = 0; i < model_.bead_count; ++i) {
        const Body& bead = bodies_[std::size_t(i)];
        const double distance = normal.dot(bead.centre - point);
        if (distance > bead.radius * (1.0 + kTouching)) continue;
        if (distance < bead.radius * (1.0 - kTouching))
          throw InvalidInput(bead_name(model_, i) + " is " + to_text(bead.radius - distance) +
                             " m into walls[" + std::to_string(w) +
                             "]; allowed: touching it within " + to_text(kTouching) +
                             " of its radius, or apart");
        add_contact(
            {.first = i, .wall = int(w), .normal = normal, .rest = normal.dot(bead.centre)},
            granular::hertz_stiffness_wall(bead.radius, bead.material, scene_.walls[w].material),
            bead.material, scene_.walls[w].material);
      }
    }
  }

  // A striker touches its target at arrival, placed back along its velocity by its gap; it
  // touches any other bead it reaches there, and may overlap none.
  void place_strikers(const granular::CellGrid& beads) {
    for (std::size_t s = 0; s < scene_.strikers.size(); ++s) {
      const StrikerSpec& spec = scene_.strikers[s];
      const std::string name = "strikers[" + std::to_string(s) + "]";
      const Eigen::Index target = body_of_target(model_, spec.target);
      if (target >= model_.bead_count)
        throw InvalidInput(invalid_value_message(
            name + ".target[0]", spec.target[0],
            "a bead in [0, " + std::to_string(model_.bead_count) + "): aimed at nothing"));
      const Vector velocity = vector_of(spec.velocity);
      const Vector direction = velocity.normalized();
      const Body& aimed = bodies_[std::size_t(target)];
      const Vector arrival = aimed.centre + arrival_offset(spec, aimed.radius, direction, name);
      const Eigen::Index body = Eigen::Index(bodies_.size());
      bodies_.push_back({arrival - spec.gap * direction, spec.radius, spec.material, velocity});
      if (!spec.spin.empty())
        bodies_.back().spin.tail(spec.spin.size()) =
            Eigen::Map<const Eigen::VectorXd>(spec.spin.data(), Eigen::Index(spec.spin.size()));
      largest_radius_ = std::max(largest_radius_, spec.radius);
      model_.striker_arrivals.push_back(spec.gap / velocity.norm());
      near(beads, arrival, (spec.radius + largest_radius_) * (1.0 + kTouching),
           [&](Eigen::Index j) { touch_striker(body, j, arrival, name); });
      check_striker_place(body, name);
    }
  }

  // Where a striker touches its target, from the target's centre: back along its flight, and
  // across it by its offset (in the plane, to the left of its flight); an offset of the sum of
  // the radii or more misses the target.
  Vector arrival_offset(const StrikerSpec& spec, double target_radius, const Vector& direction,
                        const std::string& name) const {
    const double reach = target_radius + spec.radius;
    Vector across = Vector::Zero(direction.size());
    if (spec.offset.size() == 1)
      across << -direction(1) * spec.offset[0], direction(0) * spec.offset[0];
    else if (!spec.offset.empty())
      across = vector_of(spec.offset);
    const double offset = across.norm();
    if (!(offset < reach))
      throw InvalidInput(invalid_value_message(
          name + ".offset", spec.offset.size() == 1 ? spec.offset[0] : offset,
          "|offset| < " + to_text(reach) +
              " m, the sum of the striker's and its target's radii: further out it misses"));
    return across - std::sqrt((reach - offset) * (reach + offset)) * direction;
  }

  // contact j-striker with the normal at arrival, g = 0 there; an overlap there is an error
  void touch_striker(Eigen::Index striker, Eigen::Index bead, const Vector& arrival,
                     const std::string& name) {
    const Body& s = bodies_[std::size_t(striker)];
    const Body& b = bodies_[std::size_t(bead)];
    const Vector between = b.centre - arrival;
    const double distance = between.norm(), reach = s.radius + b.radius;
    if (distance > reach * (1.0 + kTouching)) return;
    if (distance < reach * (1.0 - kTouching))
      throw InvalidInput(name + " would overlap " + bead_name(model_, bead) + " by " +
                         to_text(reach - distance) +
                         " m where it reaches its target; allowed: a striker that touches its "
                         "target and overlaps no other bead");
    const Vector normal = -between / distance;  // from the bead to the striker
    // g = n . (q_striker - q_bead) - rest, zero at arrival
    add_contact({.first = bead,
                 .second = striker,
                 .normal = normal,
                 .rest = normal.dot(arrival - b.centre)},
                granular::hertz_stiffness(b.radius, b.material, s.radius, s.material), b.material,
                s.material);
  }

  // where a striker starts: in no wall, on no other striker
  void check_striker_place(Eigen::Index striker, const std::string& name) const {
    const Body& s = bodies_[std::size_t(striker)];
    for (std::size_t w = 0; w < model_.wall_points.size(); ++w)
      if (model_.wall_normals[w].dot(s.centre - model_.wall_points[w]) < s.radius)
        throw InvalidInput(name + " starts in walls[" + std::to_string(w) +
                           "]; allowed: a striker that flies clear of the walls");
    for (Eigen::Index other = model_.bead_count; other < striker; ++other) {
      const Body& o = bodies_[std::size_t(other)];
      if ((o.centre - s.centre).norm() < o.radius + s.radius)
        throw InvalidInput(name + " starts on " + bead_name(model_, other) +
                           "; allowed: strikers apart from each other");
    }
  }

  void assemble() {
    const Eigen::Index n = Eigen::Index(bodies_.size()), m = model_.contact_count();
    const int d = model_.dimension;
    model_.radius.resize(n);
    model_.position.resize(n, d);
    model_.mass.resize(d * n);
    model_.velocity.resize(d * n);
    for (Eigen::Index b = 0; b < n; ++b) {
      const Body& body = bodies_[std::size_t(b)];
      const double mass = granular::bead_mass(body.radius, body.material);
      if (!(mass > 0.0 && std::isfinite(mass)))
        throw InvalidInput(bead_name(model_, b) + ": " +
                           invalid_value_message("mass", mass, "a finite mass > 0 kg") +
                           "; check its radius and density");
      model_.radius(b) = body.radius;
      model_.position.row(b) = body.centre.transpose();
      model_.mass.segment(d * b, d).setConstant(mass);
      model_.velocity.segment(d * b, d) = body.velocity;
    }
    std::vector<Eigen::Triplet<double>> gradients;
    auto add = [&](Eigen::Index body, Eigen::Index contact, const Vector& direction) {
      for (int k = 0; k < d; ++k)  // orthogonal contacts share no entry (a square lattice)
        if (direction(k) != 0.0) gradients.emplace_back(d * body + k, contact, direction(k));
    };
    for (Eigen::Index c = 0; c < m; ++c) {
      const PackingContact& contact = model_.contacts[std::size_t(c)];
      if (contact.second < 0) {
        add(contact.first, c, contact.normal);
      } else {
        add(contact.first, c, -contact.normal);
        add(contact.second, c, contact.normal);
      }
    }
    model_.W.resize(d * n, m);
    model_.W.setFromTriplets(gradients.begin(), gradients.end());
    model_.H = numerics::assemble_delassus(model_.W, model_.mass.cwiseInverse());
    model_.u_minus = model_.W.transpose() * model_.velocity;
    if (!(model_.u_minus.size() > 0 && model_.u_minus.minCoeff() < 0.0))
      throw InvalidInput(
          "no striker approaches its target: the packing is struck by nothing; allowed: a "
          "striker whose velocity points at the bead it targets");
    granular::check_impact_scales(model_);
    model_.beads = std::make_shared<const granular::BeadGeometry>(bead_geometry());
    add_rotation();
  }

  // The bodies turn when a contact rubs or a body spins (docs/model.md, section 16).
  void add_rotation() {
    const int components = model_.dimension == 3 ? 3 : 1;
    Eigen::VectorXd spin(components * model_.body_count());
    for (Eigen::Index b = 0; b < model_.body_count(); ++b)
      spin.segment(components * b, components) = bodies_[std::size_t(b)].spin.tail(components);
    const bool rubs =
        std::any_of(model_.laws.begin(), model_.laws.end(),
                    [](const numerics::ContactLaw& law) { return law.friction > 0.0; });
    if (!rubs && spin.isZero(0.0)) return;
    std::vector<granular::RubbingContact> contacts;
    for (const PackingContact& c : model_.contacts)
      contacts.push_back({c.first, c.second, point_of(c.normal)});
    model_.rotation = granular::build_rotation({.dimension = model_.dimension,
                                                .mass = model_.mass,
                                                .velocity = model_.velocity,
                                                .W = model_.W,
                                                .radius = model_.radius,
                                                .angular_velocity = spin,
                                                .contacts = contacts,
                                                .laws = model_.laws});
  }

  // the same bodies as spheres, for the moving geometry
  granular::BeadGeometry bead_geometry() const {
    granular::BeadGeometry beads;
    beads.dimension = model_.dimension;
    const auto padded = [](const Vector& x) {
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      p.head(x.size()) = x;
      return p;
    };
    beads.radius = model_.radius;
    beads.mass.resize(model_.body_count());
    for (const Body& body : bodies_) {
      beads.position.push_back(padded(body.centre));
      beads.material.push_back(body.material);
    }
    for (Eigen::Index b = 0; b < model_.body_count(); ++b)
      beads.mass(b) = model_.mass(model_.dimension * b);
    for (std::size_t w = 0; w < model_.wall_points.size(); ++w) {
      beads.walls.push_back({padded(model_.wall_points[w]), padded(model_.wall_normals[w])});
      beads.wall_material.push_back(scene_.walls[w].material);
    }
    beads.shape = scene_.contact.law(0.0);
    beads.fixed_stiffness = scene_.contact.stiffness.value_or(0.0);
    if (!scene_.contact.pairs.empty())
      beads.friction_between = [contact = scene_.contact](const granular::Material& a,
                                                          const granular::Material& b) {
        return contact.friction_of(a, b);
      };
    for (const PackingContact& c : model_.contacts)
      beads.closed.emplace_back(std::int32_t(c.first),
                                c.second >= 0 ? std::int32_t(c.second) : std::int32_t(-1 - c.wall));
    return beads;
  }

  const PackingScene& scene_;
  PackingModel& model_;
  const granular::RunLimits& limits_;
  std::vector<Body> bodies_;
  double largest_radius_ = 0.0;
};

}  // namespace

PackingModel build_packing_model(const PackingScene& scene, const granular::RunLimits& limits) {
  PackingModel model;
  PackingBuilder(scene, model, limits).build();
  return model;
}

Eigen::Index body_of_target(const PackingModel& model, const std::vector<int>& target) {
  if (model.columns == 0) return target[0];
  if (model.layers == 0) return Eigen::Index(target[0]) * model.columns + target[1];
  return (Eigen::Index(target[0]) * model.rows + target[1]) * model.columns + target[2];
}

namespace {

// A body's coordinates in the kernel: its translations, then its rotation when the bodies turn
// (an angle about z in the plane, a rotation vector in space: the impact sees their velocities
// only).
std::shared_ptr<kernel::LagrangianLinearTIDS> kernel_body(const PackingModel& model,
                                                          Eigen::Index b) {
  const int d = model.dimension;
  const int r = model.rotation ? model.rotation->components : 0;
  kernel::LagrangianLinearTIDS::Matrices matrices;
  Eigen::VectorXd diagonal(d + r), q = Eigen::VectorXd::Zero(d + r), v(d + r);
  diagonal.head(d).setConstant(model.mass(d * b));
  q.head(d) = model.position.row(b).transpose();
  v.head(d) = model.of(model.velocity, b);
  if (r > 0) {
    diagonal.tail(r).setConstant(model.rotation->inertia(b));
    v.tail(r) = model.rotation->of(model.rotation->angular_velocity, b);
  }
  matrices.mass = diagonal.asDiagonal();
  return std::make_shared<kernel::LagrangianLinearTIDS>(q, v, matrices,
                                                        "body " + std::to_string(b));
}

// Contact c's tangent rows over its bodies' kernel coordinates (Rotation's W_t and R_t).
Eigen::MatrixXd kernel_tangents(const PackingModel& model, std::size_t c,
                                std::initializer_list<Eigen::Index> bodies) {
  if (!model.rotation) return {};
  const granular::Rotation& rotation = *model.rotation;
  const int d = model.dimension, r = rotation.components;
  const Eigen::Index first = rotation.tangential.first_row[c];
  Eigen::MatrixXd rows(rotation.tangential.rows_of(Eigen::Index(c)),
                       Eigen::Index(bodies.size()) * (d + r));
  for (Eigen::Index row = 0; row < rows.rows(); ++row) {
    Eigen::Index column = 0;
    for (Eigen::Index b : bodies) {
      for (int k = 0; k < d; ++k) rows(row, column++) = rotation.W_t.coeff(d * b + k, first + row);
      for (int k = 0; k < r; ++k) rows(row, column++) = rotation.R_t.coeff(r * b + k, first + row);
    }
  }
  return rows;
}

}  // namespace

std::shared_ptr<kernel::NonSmoothDynamicalSystem> build_packing_system(const PackingModel& model) {
  auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  std::vector<std::shared_ptr<kernel::DynamicalSystem>> bodies;
  for (Eigen::Index b = 0; b < model.body_count(); ++b) {
    bodies.push_back(kernel_body(model, b));
    system->add(bodies.back());
  }
  const int coordinates = int(bodies.front()->dimension());
  for (std::size_t c = 0; c < model.contacts.size(); ++c) {
    const PackingContact& contact = model.contacts[c];
    const Vector& n_c = contact.normal;
    auto law = std::make_shared<plugins::LzbLaw>(model.laws[c]);
    const std::string name = "contact " + std::to_string(c);
    if (contact.second < 0) {
      Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(coordinates);
      row.head(n_c.size()) = n_c.transpose();
      auto relation = std::make_shared<kernel::LinearRelation>(
          row, -contact.rest, kernel_tangents(model, c, {contact.first}));
      system->add(std::make_shared<kernel::Interaction>(bodies[std::size_t(contact.first)],
                                                        relation, law, name));
    } else {
      Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(2 * coordinates);
      row.head(n_c.size()) = -n_c.transpose();
      row.segment(coordinates, n_c.size()) = n_c.transpose();
      auto relation = std::make_shared<kernel::LinearRelation>(
          row, -contact.rest, kernel_tangents(model, c, {contact.first, contact.second}));
      system->add(std::make_shared<kernel::Interaction>(bodies[std::size_t(contact.first)],
                                                        bodies[std::size_t(contact.second)],
                                                        relation, law, name));
    }
  }
  return system;
}

Vector momentum(const PackingModel& model, const Eigen::VectorXd& velocity) {
  Vector total = Vector::Zero(model.dimension);
  for (Eigen::Index b = 0; b < model.body_count(); ++b)
    total += model.mass(model.dimension * b) * model.of(velocity, b);
  return total;
}

Vector angular_momentum(const PackingModel& model, const Eigen::VectorXd& velocity,
                        const Eigen::VectorXd& angular_velocity, double time,
                        const Eigen::VectorXd& position) {
  const int d = model.dimension;
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (Eigen::Index b = 0; b < model.body_count(); ++b) {
    const Vector at =
        position.size() > 0
            ? model.of(position, b)
            : Vector(model.position.row(b).transpose() + model.of(model.velocity, b) * time);
    total += model.mass(d * b) * point_of(at).cross(point_of(model.of(velocity, b)));
    if (angular_velocity.size() == 0) continue;
    const double inertia = model.rotation->inertia(b);
    if (d == 2)
      total.z() += inertia * angular_velocity(b);
    else
      total += inertia * Eigen::Vector3d(angular_velocity.segment<3>(3 * b));
  }
  if (d == 3) return total;
  Vector about_z(1);
  about_z(0) = total.z();
  return about_z;
}

}  // namespace mimpact::packings
