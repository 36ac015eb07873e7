#include "mimpact/packings/packing_model.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

#include "mimpact/common/error.hpp"
#include "mimpact/granular/run_limits.hpp"
#include "mimpact/kernel/json_document.hpp"
#include "mimpact/numerics/delassus.hpp"
#include "packing_beads.hpp"

namespace mimpact::packings {

namespace {

// bytes per entry of H = W^T M^-1 W as the runs hold it: its value and index, the triplets it is
// assembled from and the products of its assembly (3 beads touching 3 000 walls took 965 MB)
constexpr double kDelassusEntryBytes = 48.0;

std::string bead_name(const PackingModel& model, Eigen::Index body) {
  if (body >= model.bead_count) return "strikers[" + std::to_string(body - model.bead_count) + "]";
  if (model.columns == 0) return "bead " + std::to_string(body);
  const Eigen::Index row = body / model.columns;
  const std::string layer =
      model.layers > 0 ? "layer " + std::to_string(row / model.rows) + ", " : std::string();
  return "bead " + std::to_string(body) + " (" + layer + "row " +
         std::to_string(model.layers > 0 ? row % model.rows : row) + ", column " +
         std::to_string(body % model.columns) + ")";
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
    const TouchIndex beads(bodies_, model_.dimension, kTouching);
    find_bead_contacts(beads);
    place_walls();
    place_strikers(beads);
    check_model_memory();
    model_.touching_tolerance = 2.0 * largest_radius_ * kTouching;
    assemble();
  }

 private:
  // the contact of materials a and b: Hertz's stiffness and their pair's friction
  void add_contact(PackingContact contact, double hertz_stiffness, const granular::Material& a,
                   const granular::Material& b) {
    granular::check_stiffness(hertz_stiffness, contact_name(contact), a, b);
    model_.contacts.push_back(contact);
    model_.laws.push_back(scene_.contact.law(hertz_stiffness));
    model_.laws.back().friction = scene_.contact.friction_of(a, b);
  }

  // its bodies by the scene's names: "bead 3 (row 1, column 0) and walls[1]"
  std::string contact_name(const PackingContact& contact) const {
    return bead_name(model_, contact.first) + " and " +
           (contact.second < 0 ? "walls[" + std::to_string(contact.wall) + "]"
                               : bead_name(model_, contact.second));
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
  void find_bead_contacts(const TouchIndex& beads) {
    for (Eigen::Index i = 0; i < model_.bead_count; ++i) {
      const Body& bead = bodies_[std::size_t(i)];
      beads.visit(bead.centre, bead.radius, [&](Eigen::Index j) {
        if (j > i) touch(i, j, bead.centre);
      });
    }
  }

  // the line of a wall given by its side: touching the outermost beads
  void wall_line(const WallSpec& wall, Vector& point, Vector& normal) const {
    if (!wall.side) {
      point = vector_of(wall.point);
      normal = vector_of(wall.normal).stableNormalized();  // [0, 1e-158] too
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

  // Two walls on one plane (the same normal, their points within kTouching of the largest
  // radius along it) are one wall given twice: refused, each would take the same impacts.
  void check_distinct_walls() const {
    const std::size_t count = model_.wall_normals.size();
    std::vector<std::size_t> order(count);
    std::iota(order.begin(), order.end(), 0);
    auto key = [&](std::size_t w) {
      const Vector& n = model_.wall_normals[w];
      return std::make_tuple(n(0), n(1), n.size() > 2 ? n(2) : 0.0, n.dot(model_.wall_points[w]));
    };
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
    std::size_t first = count, again = count;  // the duplicate of lowest index, and its original
    for (std::size_t k = 1; k < count; ++k) {
      const std::size_t a = order[k - 1], b = order[k];
      const Vector& n = model_.wall_normals[a];
      if ((n - model_.wall_normals[b]).lpNorm<Eigen::Infinity>() <= 1e-15 &&
          std::abs(n.dot(model_.wall_points[b] - model_.wall_points[a])) <=
              kTouching * largest_radius_ &&
          std::max(a, b) < again)
        std::tie(first, again) = std::minmax(a, b);
    }
    if (again < count)
      throw InvalidInput("walls[" + std::to_string(again) + "] is walls[" + std::to_string(first) +
                         "] again (the same plane); allowed: distinct walls");
  }

  void place_walls() {
    for (std::size_t w = 0; w < scene_.walls.size(); ++w) {
      Vector point, normal;
      wall_line(scene_.walls[w], point, normal);
      model_.wall_points.push_back(point);
      model_.wall_normals.push_back(normal);
    }
    check_distinct_walls();
    for (std::size_t w = 0; w < scene_.walls.size(); ++w) {
      const Vector& point = model_.wall_points[w];
      const Vector& normal = model_.wall_normals[w];
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
  void place_strikers(const TouchIndex& beads) {
    for (std::size_t s = 0; s < scene_.strikers.size(); ++s) {
      const StrikerSpec& spec = scene_.strikers[s];
      const std::string name = "strikers[" + std::to_string(s) + "]";
      const Eigen::Index target = body_of_target(model_, spec.target);
      if (target >= model_.bead_count)
        throw InvalidInput(invalid_value_message(
            name + ".target[0]", spec.target[0],
            "a bead in [0, " + std::to_string(model_.bead_count) + "): aimed at nothing"));
      const Vector velocity = vector_of(spec.velocity);
      const Vector direction = velocity.stableNormalized();
      const Body& aimed = bodies_[std::size_t(target)];
      granular::check_striker_gap(spec.gap, spec.radius + aimed.radius, name + ".gap");
      const Vector arrival = aimed.centre + arrival_offset(spec, aimed.radius, direction, name);
      const Eigen::Index body = Eigen::Index(bodies_.size());
      bodies_.push_back({arrival - spec.gap * direction, spec.radius, spec.material, velocity});
      if (!spec.spin.empty())
        bodies_.back().spin.tail(spec.spin.size()) =
            Eigen::Map<const Eigen::VectorXd>(spec.spin.data(), Eigen::Index(spec.spin.size()));
      largest_radius_ = std::max(largest_radius_, spec.radius);
      model_.striker_arrivals.push_back(spec.gap / velocity.stableNorm());
      beads.visit(arrival, spec.radius,
                  [&](Eigen::Index j) { touch_striker(body, j, arrival, name); });
      check_striker_place(beads, body, name);
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

  // The model's memory before it is assembled: its bodies and contacts, and H = W^T M^-1 W,
  // an entry for every two contacts that share a body (a bead ringed by n others: n^2).
  void check_model_memory() const {
    std::vector<double> contacts_of(bodies_.size(), 0.0);
    for (const PackingContact& c : model_.contacts) {
      contacts_of[std::size_t(c.first)] += 1.0;
      if (c.second >= 0) contacts_of[std::size_t(c.second)] += 1.0;
    }
    double entries = 0.0;
    for (double n : contacts_of) entries += n * n;
    granular::check_memory(granular::model_bytes(double(bodies_.size()),
                                                 double(model_.contacts.size()), model_.dimension) +
                               kDelassusEntryBytes * entries,
                           "the packing (" + std::to_string(bodies_.size()) + " bodies, " +
                               std::to_string(model_.contacts.size()) + " contacts, " +
                               to_text(entries) + " pairs of contacts sharing a body)",
                           limits_);
  }

  // where a striker starts: in no wall, in no bead (touching within kTouching), on no other
  // striker
  void check_striker_place(const TouchIndex& beads, Eigen::Index striker,
                           const std::string& name) const {
    const Body& s = bodies_[std::size_t(striker)];
    beads.visit(s.centre, s.radius, [&](Eigen::Index j) {
      const Body& b = bodies_[std::size_t(j)];
      const double reach = s.radius + b.radius, distance = (b.centre - s.centre).stableNorm();
      if (distance < reach * (1.0 - kTouching))
        throw InvalidInput(
            name +
            ".gap = " + to_text(scene_.strikers[std::size_t(striker - model_.bead_count)].gap) +
            " m starts it " + to_text(reach - distance) + " m into " + bead_name(model_, j) +
            " (back along its velocity from where it touches its target); allowed: a gap that "
            "starts it clear of the beads");
    });
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
    granular::check_impact_scales(
        model_, [&](Eigen::Index c) { return contact_name(model_.contacts[std::size_t(c)]); });
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

}  // namespace mimpact::packings
