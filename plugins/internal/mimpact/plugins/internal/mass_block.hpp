#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <string>

#include "mimpact/common/error.hpp"
#include "mimpact/kernel/non_smooth_dynamical_system.hpp"

namespace mimpact::plugins::internal {

// One body's block of the mass matrix, factorized: its inverse diagonal, or its Cholesky factor
// where M is full (a rocking block), refreshed only when M depends on q. Shared by the
// event-driven scheme's contact dynamics and the compliant integrator.
struct MassBlock {
  kernel::Index offset = 0, size = 0;  // in the system's global coordinates
  bool diagonal = false, constant = false, factorized = false;
  kernel::VectorXd inverse_diagonal;
  Eigen::LLT<kernel::MatrixXd> cholesky;
  kernel::MatrixXd mass;                 // workspace of refresh()
  mutable kernel::VectorXd q, v, force;  // workspaces of the callers' right-hand sides

  // The block of system k of `system`, not yet factorized.
  void describe(const kernel::NonSmoothDynamicalSystem& system, kernel::Index k) {
    const kernel::DynamicalSystem& body = system.system(k);
    offset = system.offset(k);
    size = body.dimension();
    diagonal = body.mass_is_diagonal();
    constant = body.mass_is_constant();
    factorized = false;
    mass.setZero(size, size);
    q.setZero(size);
    v = force = q;
  }

  // M(q_block) factorized again unless it is constant and factorized already; true when it
  // was. Throws Error when a full M stops being positive definite.
  bool refresh(const kernel::DynamicalSystem& body, const kernel::VectorXd& q_block) {
    if (constant && factorized) return false;
    body.mass(q_block, mass);
    if (diagonal) {
      inverse_diagonal = mass.diagonal().cwiseInverse();
    } else {
      cholesky.compute(mass);
      if (cholesky.info() != Eigen::Success)
        throw Error("system '" + body.name() +
                    "': M(q) stopped being positive definite during the motion");
    }
    factorized = true;
    return true;
  }

  // x := M^-1 x, with the last factorization.
  template <class Vector>
  void apply_inverse(Vector&& x) const {
    if (diagonal)
      x = x.cwiseProduct(inverse_diagonal);
    else
      cholesky.solveInPlace(x);
  }
};

}  // namespace mimpact::plugins::internal
