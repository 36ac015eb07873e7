#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mimpact/analysis/lzb_convergence.hpp"
#include "mimpact/chains/chain_scene.hpp"
#include "mimpact/granular/contact_model.hpp"
#include "mimpact/granular/run_limits.hpp"
#include "mimpact/kernel/non_smooth_dynamical_system.hpp"
#include "mimpact/numerics/contact_law.hpp"

namespace mimpact::chains {

// A chain of beads on a line (docs/model.md, section 8): the beads touch, strikers may fly towards
// either end first, a rigid wall may touch the last bead. Bodies left to right (a left
// striker, the beads, a right striker); contact i joins bodies i and i + 1,
// g_i = x_{i+1} - x_i - (R_i + R_{i+1}); the wall's contact is last, g = x_wall - x_N - R_N.
struct ChainModel : granular::ContactModel {
  Eigen::VectorXd radius;    // m, per body
  Eigen::VectorXd position;  // m, of the centres at t = 0 (first bead at 0)
  bool has_wall = false;
  double wall_position = 0.0;  // m, of the wall's plane
  Eigen::Index first_bead = 0;
};

// Throws InvalidInput for a chain that needs more memory than `limits` allow, and for bodies
// whose masses leave double precision.
ChainModel build_chain_model(const ChainScene& scene, const granular::RunLimits& limits = {});

// The chain in the kernel's terms: one LagrangianLinearTIDS per body (no force), one
// interaction per contact with a LinearRelation and an LzbLaw.
std::shared_ptr<kernel::NonSmoothDynamicalSystem> build_chain_system(const ChainModel& model);

// The chain's one impact for the convergence study of Nguyen & Brogliato (2011) (appendix A.2): H,
// u-, the laws, M^-1 W and v-. Throws InvalidInput when a striker starts away from the chain (more
// than one impact).
analysis::ImpactProblemData impact_problem(const ChainModel& model);

// Where contact j touches at t = 0 (m), from the centre of the first body: x_j + R_j, or
// the wall's plane for the wall's contact.
double contact_position(const ChainModel& model, Eigen::Index contact);

// Total momentum (N s) of the chain moving with `velocity`.
double momentum(const ChainModel& model, const Eigen::VectorXd& velocity);

}  // namespace mimpact::chains
