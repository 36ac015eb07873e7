#pragma once

#include <Eigen/Dense>
#include <string>

namespace mimpact::kernel {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

// A mechanical system in Lagrangian form, M(q) q'' = F(t, q, q') with F = F_ext - F_int:
// generalized coordinates q, their velocities v = q', a symmetric positive definite mass
// matrix. Concrete kinds: LagrangianDS (callables), LagrangianLinearTIDS (constant matrices).
class DynamicalSystem {
 public:
  // Throws InvalidInput when the sizes differ or an entry is not finite.
  DynamicalSystem(VectorXd position, VectorXd velocity, std::string name);
  virtual ~DynamicalSystem() = default;

  Index dimension() const { return position_.size(); }
  const std::string& name() const { return name_; }
  const VectorXd& position() const { return position_; }
  const VectorXd& velocity() const { return velocity_; }
  void set_state(const Eigen::Ref<const VectorXd>& position,
                 const Eigen::Ref<const VectorXd>& velocity);

  // M(q) into `mass`, already dimension x dimension.
  virtual void mass(const VectorXd& q, MatrixXd& mass) const = 0;
  virtual bool mass_is_constant() const = 0;
  virtual bool mass_is_diagonal() const = 0;
  // F(t, q, v) into `force`, already of size dimension.
  virtual void force(double t, const VectorXd& q, const VectorXd& v, VectorXd& force) const = 0;
  // False when F is zero at all times: between events the motion is then q + v t, and no
  // differential equation needs integrating.
  virtual bool has_force() const = 0;

  // Throws InvalidInput naming the system when M at the current position is not symmetric
  // positive definite (a non-positive mass).
  void check_mass() const;

 private:
  VectorXd position_;
  VectorXd velocity_;
  std::string name_;
};

}  // namespace mimpact::kernel
