#pragma once

#include "mimpact/kernel/dynamical_system.hpp"

namespace mimpact::kernel {

// A linear time-invariant Lagrangian system: M q'' + C q' + K q = F_ext, every matrix
// constant. Empty K, C or F_ext mean zero.
class LagrangianLinearTIDS : public DynamicalSystem {
 public:
  struct Matrices {
    MatrixXd mass;
    MatrixXd stiffness;       // K, empty for none
    MatrixXd damping;         // C, empty for none
    VectorXd external_force;  // F_ext, empty for none
  };
  // Throws InvalidInput naming the matrix whose size disagrees with q.
  LagrangianLinearTIDS(VectorXd position, VectorXd velocity, Matrices matrices,
                       std::string name = "");

  void mass(const VectorXd& q, MatrixXd& mass) const override;
  bool mass_is_constant() const override { return true; }
  bool mass_is_diagonal() const override { return diagonal_; }
  void force(double t, const VectorXd& q, const VectorXd& v, VectorXd& force) const override;
  bool has_force() const override;

 private:
  Matrices matrices_;
  bool diagonal_;
};

}  // namespace mimpact::kernel
