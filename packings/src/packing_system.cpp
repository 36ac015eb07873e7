// The packing in the kernel's terms (build_packing_system) and its momenta.
#include <Eigen/Dense>
#include <memory>
#include <string>
#include <vector>

#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/linear_relation.hpp"
#include "mimpact/packings/packing_model.hpp"
#include "mimpact/plugins/lzb_law.hpp"
#include "packing_beads.hpp"

namespace mimpact::packings {

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
