#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <vector>

#include "mimpact/chain/chain_scene.hpp"
#include "mimpact/numerics/contact_law.hpp"

namespace mimpact::chain {

// A chain of beads on a line at the instant of impact: every gap zero, so every contact
// belongs to one multiple impact (LZB.md section 8). Bodies left to right, striker first;
// contact i joins bodies i and i + 1, g_i = x_{i+1} - x_i - (R_i + R_{i+1}).
struct ChainModel {
  Eigen::VectorXd radius;         // m, per body
  Eigen::VectorXd mass;           // kg, per body
  Eigen::VectorXd velocity;       // pre-impact velocity (m/s, > 0 to the right), per body
  Eigen::SparseMatrix<double> W;  // bodies x contacts, column i = grad g_i
  Eigen::SparseMatrix<double> H;  // W^T M^-1 W, tridiagonal
  Eigen::VectorXd u_minus;        // W^T v, pre-impact relative velocities
  std::vector<numerics::ContactLaw> laws;

  Eigen::Index body_count() const { return mass.size(); }
  Eigen::Index contact_count() const { return Eigen::Index(laws.size()); }
};

ChainModel build_chain_model(const ChainScene& scene);

// Total momentum (N s) and kinetic energy (J) of the chain moving with `velocity`.
double momentum(const ChainModel& model, const Eigen::VectorXd& velocity);
double kinetic_energy(const ChainModel& model, const Eigen::VectorXd& velocity);

}  // namespace mimpact::chain
