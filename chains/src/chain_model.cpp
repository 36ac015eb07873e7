#include "mimpact/chains/chain_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mimpact/common/error.hpp"
#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/linear_relation.hpp"
#include "mimpact/numerics/delassus.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::chains {

namespace {

struct Body {
  double radius;
  granular::Material material;
  double velocity;
};

std::vector<Body> bodies_of(const ChainScene& scene) {
  std::vector<Body> bodies;
  if (const StrikerSpec* left = scene.striker(Side::left))
    bodies.push_back({left->radius, left->material, left->velocity});
  for (const SegmentSpec& segment : scene.chain.segments)
    for (int k = 0; k < segment.count; ++k)
      bodies.push_back({segment.radius * std::pow(1.0 - segment.taper, k), segment.material, 0.0});
  for (const BeadSpec& bead : scene.chain.beads)
    bodies.push_back({bead.radius, bead.material, 0.0});
  if (const StrikerSpec* right = scene.striker(Side::right))
    bodies.push_back({right->radius, right->material, -right->velocity});
  return bodies;
}

// Presses the beads against the wall with the scene's static force F_0: every contact of the
// beads carries F_0 at overlap (F_0 / K)^(1/eta); the beads are placed from the wall back.
void precompress(ChainModel& model, const ChainScene& scene) {
  const double eta = scene.contact.exponent;
  const Eigen::Index n = model.body_count(), first_bead = model.first_bead;
  double largest_force = INFINITY;  // N: the force at which an overlap reaches the smaller radius
  for (Eigen::Index j = first_bead; j < Eigen::Index(model.laws.size()); ++j) {
    const double smaller_radius =
        j + 1 < n ? std::min(model.radius(j), model.radius(j + 1)) : model.radius(j);
    largest_force = std::min(largest_force,
                             model.laws[std::size_t(j)].stiffness * std::pow(smaller_radius, eta));
  }
  if (!(scene.precompression < largest_force))
    throw InvalidInput(invalid_value_message(
        "precompression", scene.precompression,
        "< " + to_text(largest_force) + " N, where a static overlap reaches a bead's radius"));
  model.precompression = scene.precompression;
  auto overlap = [&](Eigen::Index contact) {
    return std::pow(scene.precompression / model.laws[std::size_t(contact)].stiffness, 1.0 / eta);
  };
  for (Eigen::Index j = first_bead; j < Eigen::Index(model.laws.size()); ++j)
    model.largest_static_overlap = std::max(model.largest_static_overlap, overlap(j));
  const Eigen::Index last = n - 1;
  model.position(last) =
      model.wall_position - model.radius(last) + overlap(Eigen::Index(model.laws.size()) - 1);
  for (Eigen::Index i = last - 1; i >= first_bead; --i)
    model.position(i) = model.position(i + 1) - model.radius(i) - model.radius(i + 1) + overlap(i);
  if (const StrikerSpec* left = scene.striker(Side::left))
    model.position(0) = model.position(1) - model.radius(0) - model.radius(1) - left->gap;
}

// Touching bodies left to right, the first bead at 0; strikers off by their gaps (each within
// kFarthestGap of the radii), arriving at gap / speed.
void place_bodies(const ChainScene& scene, ChainModel& model) {
  const Eigen::Index n = model.radius.size();
  const StrikerSpec* left = scene.striker(Side::left);
  const StrikerSpec* right = scene.striker(Side::right);
  model.first_bead = left ? 1 : 0;
  model.position(model.first_bead) = 0.0;
  for (Eigen::Index i = model.first_bead + 1; i < n; ++i)
    model.position(i) = model.position(i - 1) + model.radius(i - 1) + model.radius(i);
  auto gap_field = [&](const StrikerSpec* striker) {
    return "strikers[" + std::to_string(striker - scene.strikers.data()) + "].gap";
  };
  if (left) {
    granular::check_striker_gap(left->gap, model.radius(0) + model.radius(1), gap_field(left));
    model.position(0) = -(model.radius(0) + model.radius(1)) - left->gap;
    model.striker_arrivals.push_back(left->gap / left->velocity);
  }
  if (right) {
    granular::check_striker_gap(right->gap, model.radius(n - 1) + model.radius(n - 2),
                                gap_field(right));
    model.position(n - 1) += right->gap;
    model.striker_arrivals.push_back(right->gap / right->velocity);
  }
}

// a body by the scene's name: a striker by its side, a bead by its place from the left
std::string body_name(const ChainScene& scene, const ChainModel& model, Eigen::Index body) {
  if (body < model.first_bead) return "the left striker";
  if (scene.striker(Side::right) && body == model.body_count() - 1) return "the right striker";
  return "bead " + std::to_string(body - model.first_bead);
}

}  // namespace

ChainModel build_chain_model(const ChainScene& scene, const granular::RunLimits& limits) {
  granular::check_memory(granular::model_bytes(scene.body_count(), scene.contact_count(), 1),
                         scene.chain.key() + " (" + std::to_string(scene.bead_count()) + " beads)",
                         limits);
  const std::vector<Body> bodies = bodies_of(scene);
  const Eigen::Index n = Eigen::Index(bodies.size());
  ChainModel model;
  model.radius.resize(n);
  model.mass.resize(n);
  model.position.resize(n);
  model.velocity.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    model.radius(i) = bodies[i].radius;
    model.mass(i) = granular::bead_mass(bodies[i].radius, bodies[i].material);
    model.velocity(i) = bodies[i].velocity;
    // valid fields can still multiply out of double's range: a long steep taper, a tiny radius
    if (!(model.mass(i) > 0.0 && std::isfinite(model.mass(i))))
      throw InvalidInput(
          "body " + std::to_string(i) + " (radius " + to_text(model.radius(i)) +
          " m): " + invalid_value_message("mass", model.mass(i), "a finite mass > 0 kg") +
          "; check the radii, tapers and densities of the scene");
  }
  place_bodies(scene, model);

  std::vector<Eigen::Triplet<double>> gradients;
  // A chain's beads move along its line and do not spin: its contacts never slip, so friction
  // takes no impulse there (docs/model.md, section 16) and the laws leave it out.
  // a packing's kTouching, or the rounding of a gap, a difference of positions
  model.touching_tolerance =
      std::max(2e-9 * model.radius.maxCoeff(),
               8.0 * std::numeric_limits<double>::epsilon() * model.position.cwiseAbs().maxCoeff());
  auto contact_name = [&](Eigen::Index j) {
    return body_name(scene, model, j) + " and " +
           (j + 1 < n ? body_name(scene, model, j + 1) : std::string("the wall"));
  };
  auto add_law = [&](double stiffness, const granular::Material& a, const granular::Material& b) {
    granular::check_stiffness(stiffness, contact_name(Eigen::Index(model.laws.size())), a, b);
    model.laws.push_back(scene.contact.law(stiffness));
    model.laws.back().friction = 0.0;
  };
  for (Eigen::Index i = 0; i + 1 < n; ++i) {
    gradients.emplace_back(i, i, -1.0);
    gradients.emplace_back(i + 1, i, 1.0);
    add_law(granular::hertz_stiffness(bodies[i].radius, bodies[i].material, bodies[i + 1].radius,
                                      bodies[i + 1].material),
            bodies[i].material, bodies[i + 1].material);
  }
  if (scene.wall) {
    model.has_wall = true;
    model.wall_position = model.position(n - 1) + model.radius(n - 1);
    gradients.emplace_back(n - 1, n - 1, -1.0);
    add_law(granular::hertz_stiffness_wall(bodies[n - 1].radius, bodies[n - 1].material,
                                           scene.wall->material),
            bodies[n - 1].material, scene.wall->material);
  }
  if (scene.precompression > 0.0) precompress(model, scene);
  model.W.resize(n, Eigen::Index(model.laws.size()));
  model.W.setFromTriplets(gradients.begin(), gradients.end());
  model.H = numerics::assemble_delassus(model.W, model.mass.cwiseInverse());
  model.u_minus = model.W.transpose() * model.velocity;
  granular::check_impact_scales(model, contact_name);
  return model;
}

std::shared_ptr<kernel::NonSmoothDynamicalSystem> build_chain_system(const ChainModel& model) {
  auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  std::vector<std::shared_ptr<kernel::DynamicalSystem>> bodies;
  for (Eigen::Index i = 0; i < model.body_count(); ++i) {
    kernel::LagrangianLinearTIDS::Matrices matrices;
    matrices.mass = Eigen::MatrixXd::Constant(1, 1, model.mass(i));
    if (model.precompression > 0.0 && i == model.first_bead)
      matrices.external_force = Eigen::VectorXd::Constant(1, model.precompression);
    bodies.push_back(std::make_shared<kernel::LagrangianLinearTIDS>(
        Eigen::VectorXd::Constant(1, model.position(i)),
        Eigen::VectorXd::Constant(1, model.velocity(i)), matrices, "body " + std::to_string(i)));
    system->add(bodies.back());
  }
  const Eigen::Index n = model.body_count();
  for (Eigen::Index i = 0; i + 1 < n; ++i) {
    // g = x_{i+1} - x_i - (R_i + R_{i+1}) on the stacked (x_i, x_{i+1})
    auto relation = std::make_shared<kernel::LinearRelation>(
        Eigen::RowVector2d(-1.0, 1.0), -(model.radius(i) + model.radius(i + 1)));
    system->add(std::make_shared<kernel::Interaction>(
        bodies[i], bodies[i + 1], relation, std::make_shared<plugins::LzbLaw>(model.laws[i]),
        "contact " + std::to_string(i)));
  }
  if (model.has_wall) {
    auto relation = std::make_shared<kernel::LinearRelation>(
        Eigen::RowVectorXd::Constant(1, -1.0), model.wall_position - model.radius(n - 1));
    system->add(std::make_shared<kernel::Interaction>(
        bodies[n - 1], relation, std::make_shared<plugins::LzbLaw>(model.laws.back()), "wall"));
  }
  return system;
}

analysis::ImpactProblemData impact_problem(const ChainModel& model) {
  for (double arrival : model.striker_arrivals)
    if (arrival > 0.0)
      throw InvalidInput(
          "the convergence study needs the strikers touching the chain (one impact); "
          "a striker has a gap");
  analysis::ImpactProblemData problem;
  problem.H = model.H;
  problem.u_minus = model.u_minus;
  problem.laws = model.laws;
  problem.mobility = model.mass.cwiseInverse().asDiagonal() * model.W;
  problem.velocity_before = model.velocity;
  return problem;
}

double contact_position(const ChainModel& model, Eigen::Index contact) {
  return model.position(contact) + model.radius(contact) - model.position(0);
}

double momentum(const ChainModel& model, const Eigen::VectorXd& velocity) {
  return model.mass.dot(velocity);
}

}  // namespace mimpact::chains
