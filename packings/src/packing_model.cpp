#include "mimpact/packings/packing_model.hpp"

#include <algorithm>
#include <boost/geometry.hpp>
#include <boost/geometry/index/rtree.hpp>
#include <cmath>
#include <fstream>
#include <numeric>
#include <optional>
#include <sstream>
#include <tuple>

#include "mimpact/common/error.hpp"
#include "mimpact/granular/run_limits.hpp"
#include "mimpact/kernel/json_document.hpp"
#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/linear_relation.hpp"
#include "mimpact/numerics/delassus.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::packings {

namespace {

namespace bg = boost::geometry;
namespace bgi = boost::geometry::index;
// three dimensions whatever the packing's (a planar packing's third coordinate is 0)
using Point = bg::model::point<double, 3, bg::cs::cartesian>;
using Box = bg::model::box<Point>;
using Entry = std::pair<Point, Eigen::Index>;
using Tree = bgi::rtree<Entry, bgi::rstar<16>>;

struct Body {
  Vector centre;
  double radius;
  granular::Material material;
  Vector velocity = Vector::Zero(centre.size());
  std::size_t line = 0;  // of a listed bead, in its file (for messages); 0: not listed
};

// the first `dimension` of these components
Vector vector_of(std::initializer_list<double> components, int dimension) {
  Vector v(dimension);
  std::copy_n(components.begin(), dimension, v.data());
  return v;
}
Vector vector_of(const std::vector<double>& components) {
  return Eigen::Map<const Eigen::VectorXd>(components.data(), Eigen::Index(components.size()));
}

// the R-tree's point of `centre`, shifted by `by` along every axis
Point point_of(const Vector& centre, double by = 0.0) {
  Eigen::Vector3d at = Eigen::Vector3d::Zero();
  at.head(centre.size()) = centre;
  return Point(at(0) + by, at(1) + by, at(2) + by);
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

std::vector<Body> lattice_beads(const LatticeSpec& lattice) {
  std::vector<Body> beads;
  const double a = lattice.radius;
  const int d = lattice_dimension(lattice.type);
  const bool close_packed =
      lattice.type != LatticeType::square && lattice.type != LatticeType::simple_cubic;
  const double row_pitch = close_packed ? std::sqrt(3.0) * a : 2.0 * a;
  const double layer_pitch = close_packed ? 2.0 * std::sqrt(2.0 / 3.0) * a : 2.0 * a;
  // the layers' stacking: FCC shifts each layer by (a, a / sqrt(3)) from the one below, three
  // positions in turn; HCP alternates two
  const int positions = lattice.type == LatticeType::fcc   ? 3
                        : lattice.type == LatticeType::hcp ? 2
                                                           : 1;
  const int layers = std::max(lattice.layers, 1);
  beads.reserve(std::size_t(layers) * std::size_t(lattice.rows) * std::size_t(lattice.columns));
  for (int l = 0; l < layers; ++l) {
    const double stacking = double(l % positions);
    for (int r = 0; r < lattice.rows; ++r)
      for (int c = 0; c < lattice.columns; ++c) {
        const double shift = close_packed && r % 2 == 1 ? a : 0.0;
        beads.push_back({vector_of({2.0 * a * c + shift + stacking * a,
                                    row_pitch * r + stacking * a / std::sqrt(3.0), layer_pitch * l},
                                   d),
                         a, lattice.material});
      }
  }
  return beads;
}

// The memory a bead takes with its contacts (a bead touches 3 others on average in the plane, 6
// in space)
double bead_bytes(int dimension) {
  return granular::model_bytes(1.0, 3.0 * (dimension - 1), dimension);
}

// The bead list's file: inside `directory` (the scene's, or --data-dir), a regular file. Its
// path is the scene's, so messages may name it; its content is never echoed.
std::filesystem::path bead_file(const BeadListSpec& list, const std::filesystem::path& directory) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path root = fs::weakly_canonical(fs::absolute(directory, error), error);
  const fs::path path = fs::weakly_canonical(fs::absolute(directory / list.file, error), error);
  const auto [outside, _] = std::mismatch(root.begin(), root.end(), path.begin(), path.end());
  if (list.file.empty() || outside != root.end())
    throw InvalidInput("beads.file = " + kernel::json_excerpt(nlohmann::json(list.file)) +
                       " is not inside " + root.string() +
                       "; allowed: a file in the scene's directory or below it (--data-dir, or "
                       "data_dir= in Python, chooses another directory)");
  const fs::file_status status = fs::status(path, error);
  if (!fs::exists(status)) throw InvalidInput("beads.file: " + path.string() + " does not exist");
  if (!fs::is_regular_file(status))
    throw InvalidInput("beads.file: " + path.string() +
                       " is not a regular file (a directory, device or pipe); allowed: a CSV file");
  return path;
}

// "x,y,radius": the header of these columns
std::string line_of(const char* const* names, int columns) {
  std::string line = names[0];
  for (int k = 1; k < columns; ++k) (line += ",") += names[k];
  return line;
}

// A cell of the list as a number: the whole cell, spaces aside, and finite.
std::optional<double> number_of(std::string cell) {
  const std::size_t first = cell.find_first_not_of(" \t\r");
  const std::size_t last = cell.find_last_not_of(" \t\r");
  if (first == std::string::npos) return std::nullopt;
  cell = cell.substr(first, last - first + 1);
  char* end = nullptr;
  const double value = std::strtod(cell.c_str(), &end);
  if (end != cell.c_str() + cell.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

// "x,y,radius" (the plane) or "x,y,z,radius" (space), then one bead per line. Messages name the
// line and column, never their content (a scene from elsewhere must not make mimpact show a
// file's lines).
std::vector<Body> listed_beads(const BeadListSpec& list, const std::filesystem::path& directory,
                               const granular::RunLimits& limits) {
  const std::filesystem::path path = bead_file(list, directory);
  std::ifstream in(path);
  if (!in) throw InvalidInput("beads.file: cannot open " + path.string() + " for reading");
  auto fail = [&](std::size_t line, const std::string& what) -> void {
    throw InvalidInput(path.string() + " line " + std::to_string(line) + ": " + what);
  };
  std::string line;
  std::getline(in, line);
  if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte-order mark
  if (line.find_last_not_of(" \t\r") != std::string::npos)
    line.erase(line.find_last_not_of(" \t\r") + 1);
  if (line != "x,y,radius" && line != "x,y,z,radius")
    fail(1, "is not the header; allowed: x,y,radius or x,y,z,radius (m)");
  const int dimension = line == "x,y,radius" ? 2 : 3;
  const int columns = dimension + 1;
  static const char* const kNames[2][4] = {{"x", "y", "radius"}, {"x", "y", "z", "radius"}};
  const char* const* names = kNames[dimension - 2];
  std::vector<Body> beads;
  for (std::size_t number = 2; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream fields(line);
    std::string cell;
    double values[4];
    int count = 0;
    for (; std::getline(fields, cell, ','); ++count) {
      if (count == columns)
        fail(number, "more than " + std::to_string(columns) +
                         " columns; allowed: " + line_of(names, columns));
      const std::optional<double> value = number_of(cell);
      if (!value) fail(number, std::string("column ") + names[count] + " is not a finite number");
      values[count] = *value;
    }
    if (count != columns)
      fail(number, std::to_string(count) + " columns; allowed: " + line_of(names, columns));
    const double radius = values[dimension];
    if (!(radius > 0.0)) fail(number, invalid_value_message("radius", radius, "> 0 (m)"));
    beads.push_back({.centre = vector_of({values[0], values[1], values[2]}, dimension),
                     .radius = radius,
                     .material = list.material,
                     .line = number});
    if (beads.size() % 100'000 == 0)
      granular::check_memory(double(beads.size()) * bead_bytes(dimension),
                             "beads.file (" + std::to_string(beads.size()) + " beads so far)",
                             limits);
  }
  if (beads.empty())
    throw InvalidInput(path.string() + ": the bead list is empty; allowed: at least one bead");
  return beads;
}

Tree index_of(const std::vector<Body>& bodies) {
  std::vector<Entry> entries;
  entries.reserve(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i)
    entries.emplace_back(point_of(bodies[i].centre), Eigen::Index(i));
  return Tree(entries.begin(), entries.end());  // packed (bulk) loading
}

// Calls visit(j) for every body of `tree` whose centre lies within `reach` of `centre`.
template <class Visit>
void near(const Tree& tree, const Vector& centre, double reach, Visit&& visit) {
  const Box box(point_of(centre, -reach), point_of(centre, reach));
  for (auto it = tree.qbegin(bgi::intersects(box)); it != tree.qend(); ++it) visit(it->second);
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
    const Tree beads = index_of(bodies_);
    find_bead_contacts(beads);
    place_walls();
    place_strikers(beads);
    assemble();
  }

 private:
  void add_contact(PackingContact contact, double hertz_stiffness) {
    model_.contacts.push_back(contact);
    model_.laws.push_back(scene_.contact.law(hertz_stiffness));
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
                granular::hertz_stiffness(a.radius, a.material, b.radius, b.material));
  }

  void find_bead_contacts(const Tree& beads) {
    for (Eigen::Index i = 0; i < model_.bead_count; ++i) {
      const Body& bead = bodies_[std::size_t(i)];
      near(beads, bead.centre, (bead.radius + largest_radius_) * (1.0 + kTouching),
           [&](Eigen::Index j) {
             if (j > i) touch(i, j, bead.centre);
           });
    }
    // the tree hands the neighbours in its own order: contacts by their first, then second bead
    std::vector<std::size_t> order(model_.contacts.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t p, std::size_t q) {
      const PackingContact &a = model_.contacts[p], &b = model_.contacts[q];
      return std::tie(a.first, a.second) < std::tie(b.first, b.second);
    });
    std::vector<PackingContact> contacts;
    std::vector<numerics::ContactLaw> laws;
    for (std::size_t k : order) {
      contacts.push_back(model_.contacts[k]);
      laws.push_back(model_.laws[k]);
    }
    model_.contacts = std::move(contacts);
    model_.laws = std::move(laws);
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
            granular::hertz_stiffness_wall(bead.radius, bead.material, scene_.walls[w].material));
      }
    }
  }

  // A striker touches its target at arrival, placed back along its velocity by its gap; it
  // touches any other bead it reaches there, and may overlap none.
  void place_strikers(const Tree& beads) {
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
      const Vector arrival = aimed.centre - (aimed.radius + spec.radius) * direction;
      const Eigen::Index body = Eigen::Index(bodies_.size());
      bodies_.push_back({arrival - spec.gap * direction, spec.radius, spec.material, velocity});
      largest_radius_ = std::max(largest_radius_, spec.radius);
      model_.striker_arrivals.push_back(spec.gap / velocity.norm());
      near(beads, arrival, (spec.radius + largest_radius_) * (1.0 + kTouching),
           [&](Eigen::Index j) { touch_striker(body, j, arrival, name); });
      check_striker_place(body, name);
    }
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
                granular::hertz_stiffness(b.radius, b.material, s.radius, s.material));
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

std::shared_ptr<kernel::NonSmoothDynamicalSystem> build_packing_system(const PackingModel& model) {
  auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  std::vector<std::shared_ptr<kernel::DynamicalSystem>> bodies;
  const Eigen::Index n = model.body_count();
  const int d = model.dimension;
  for (Eigen::Index b = 0; b < n; ++b) {
    kernel::LagrangianLinearTIDS::Matrices matrices;
    matrices.mass = model.mass(d * b) * Eigen::MatrixXd::Identity(d, d);
    bodies.push_back(std::make_shared<kernel::LagrangianLinearTIDS>(
        Eigen::VectorXd(model.position.row(b).transpose()),
        Eigen::VectorXd(model.of(model.velocity, b)), matrices, "body " + std::to_string(b)));
    system->add(bodies.back());
  }
  for (std::size_t c = 0; c < model.contacts.size(); ++c) {
    const PackingContact& contact = model.contacts[c];
    const Vector& n_c = contact.normal;
    auto law = std::make_shared<plugins::LzbLaw>(model.laws[c]);
    const std::string name = "contact " + std::to_string(c);
    if (contact.second < 0) {
      auto relation = std::make_shared<kernel::LinearRelation>(n_c.transpose(), -contact.rest);
      system->add(std::make_shared<kernel::Interaction>(bodies[std::size_t(contact.first)],
                                                        relation, law, name));
    } else {
      Eigen::RowVectorXd row(2 * d);
      row << -n_c.transpose(), n_c.transpose();
      auto relation = std::make_shared<kernel::LinearRelation>(row, -contact.rest);
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

}  // namespace mimpact::packings
