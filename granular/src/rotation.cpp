#include "mimpact/granular/rotation.hpp"

#include <cmath>

namespace mimpact::granular {

int tangent_frame(const Eigen::Vector3d& n, int dimension, Eigen::Vector3d (&tangents)[2]) {
  if (dimension < 3) {
    tangents[0] = Eigen::Vector3d(-n.y(), n.x(), 0.0);
    return 1;
  }
  const Eigen::Vector3d axis =
      std::abs(n.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  tangents[0] = axis.cross(n).normalized();
  tangents[1] = n.cross(tangents[0]);
  return 2;
}

namespace {

// The rows' gradients, column by column: W_t (translations) and R_t (rotations).
class RowGradients {
 public:
  RowGradients(const RotationInput& input, int components)
      : input_(input), components_(components) {}

  // The rows of contact c: sigma t on each body's translations, -radius (n x t) on its rotation.
  void add(const RubbingContact& c, Eigen::Index row, const Eigen::Vector3d& t) {
    const Eigen::Vector3d lever = c.normal.cross(t);
    const auto body = [&](Eigen::Index b, double sigma) {
      for (int k = 0; k < input_.dimension; ++k)
        if (t(k) != 0.0) translations_.emplace_back(input_.dimension * b + k, row, sigma * t(k));
      const double radius = input_.radius(b);
      if (components_ == 1)
        rotations_.emplace_back(b, row, -radius * lever.z());
      else
        for (int k = 0; k < 3; ++k)
          if (lever(k) != 0.0) rotations_.emplace_back(3 * b + k, row, -radius * lever(k));
    };
    if (c.second < 0) {
      body(c.first, 1.0);
    } else {
      body(c.first, -1.0);
      body(c.second, 1.0);
    }
  }

  void fill(Rotation& rotation, Eigen::Index bodies, Eigen::Index rows) const {
    rotation.W_t.resize(input_.mass.size(), rows);
    rotation.W_t.setFromTriplets(translations_.begin(), translations_.end());
    rotation.R_t.resize(components_ * bodies, rows);
    rotation.R_t.setFromTriplets(rotations_.begin(), rotations_.end());
  }

 private:
  const RotationInput& input_;
  int components_;
  std::vector<Eigen::Triplet<double>> translations_, rotations_;
};

}  // namespace

Rotation build_rotation(const RotationInput& input) {
  Rotation rotation;
  rotation.components = input.dimension == 3 ? 3 : 1;
  const Eigen::Index bodies = input.radius.size();
  rotation.inertia.resize(bodies);
  for (Eigen::Index b = 0; b < bodies; ++b)
    rotation.inertia(b) = 0.4 * input.mass(input.dimension * b) * input.radius(b) * input.radius(b);
  rotation.angular_velocity = input.angular_velocity;
  numerics::TangentialRows& rows = rotation.tangential;
  rows.first_row.assign(input.contacts.size() + 1, 0);
  RowGradients gradients(input, rotation.components);
  Eigen::Index row = 0;
  for (std::size_t c = 0; c < input.contacts.size(); ++c) {
    if (input.laws[c].friction > 0.0) {
      Eigen::Vector3d tangents[2];
      const int count = tangent_frame(input.contacts[c].normal, input.dimension, tangents);
      for (int k = 0; k < count; ++k) gradients.add(input.contacts[c], row++, tangents[k]);
    }
    rows.first_row[c + 1] = row;
  }
  gradients.fill(rotation, bodies, row);
  // the blocks the tangent columns add to W^T M^-1 W (the rotations take no normal row)
  const Eigen::VectorXd inverse_mass = input.mass.cwiseInverse();
  Eigen::VectorXd inverse_inertia(rotation.R_t.rows());
  for (Eigen::Index b = 0; b < bodies; ++b)
    inverse_inertia.segment(rotation.components * b, rotation.components)
        .setConstant(1.0 / rotation.inertia(b));
  const Eigen::SparseMatrix<double> mobile = inverse_mass.asDiagonal() * rotation.W_t;
  rows.normal_to_tangent = Eigen::SparseMatrix<double>(mobile.transpose()) * input.W;
  rows.tangent = Eigen::SparseMatrix<double>(mobile.transpose()) * rotation.W_t +
                 Eigen::SparseMatrix<double>(rotation.R_t.transpose()) *
                     (inverse_inertia.asDiagonal() * rotation.R_t);
  rows.slip_minus =
      rotation.W_t.transpose() * input.velocity + rotation.R_t.transpose() * input.angular_velocity;
  return rotation;
}

Eigen::VectorXd turned(const Rotation& rotation, const Eigen::VectorXd& before,
                       const Eigen::VectorXd& tangential) {
  Eigen::VectorXd omega = rotation.R_t * tangential;
  for (Eigen::Index b = 0; b < rotation.body_count(); ++b)
    omega.segment(rotation.components * b, rotation.components) /= rotation.inertia(b);
  return omega + before;
}

double rotational_energy(const Rotation& rotation, const Eigen::VectorXd& angular_velocity) {
  double energy = 0.0;
  for (Eigen::Index b = 0; b < rotation.body_count(); ++b)
    energy += 0.5 * rotation.inertia(b) * rotation.of(angular_velocity, b).squaredNorm();
  return energy;
}

}  // namespace mimpact::granular
