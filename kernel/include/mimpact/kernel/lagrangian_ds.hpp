#pragma once

#include <functional>

#include "mimpact/kernel/dynamical_system.hpp"

namespace mimpact::kernel {

// A nonlinear Lagrangian system whose mass matrix and forces are user callables (the
// "plugins" of Siconos). Each callable writes into an output already of the right size;
// one that resizes it is reported as an error naming the system.
class LagrangianDS : public DynamicalSystem {
 public:
  using MassFunction = std::function<void(const VectorXd& q, MatrixXd& mass)>;
  // F_int(t, q, v), the internal forces (springs, gravity written as a potential, ...)
  using InternalForce =
      std::function<void(double t, const VectorXd& q, const VectorXd& v, VectorXd& force)>;
  // F_ext(t), the external forces
  using ExternalForce = std::function<void(double t, VectorXd& force)>;

  // A constant mass matrix (any Eigen matrix expression).
  template <class Derived>
  LagrangianDS(VectorXd position, VectorXd velocity, const Eigen::MatrixBase<Derived>& mass,
               std::string name = "")
      : LagrangianDS(std::move(position), std::move(velocity), MatrixXd(mass), std::move(name),
                     ConstantMass{}) {}
  // A configuration-dependent mass matrix M(q).
  LagrangianDS(VectorXd position, VectorXd velocity, MassFunction mass, std::string name = "");

  void set_internal_force(InternalForce internal) { internal_ = std::move(internal); }
  void set_external_force(ExternalForce external) { external_ = std::move(external); }

  void mass(const VectorXd& q, MatrixXd& mass) const override;
  bool mass_is_constant() const override { return !mass_function_; }
  bool mass_is_diagonal() const override;
  void force(double t, const VectorXd& q, const VectorXd& v, VectorXd& force) const override;
  bool has_force() const override { return internal_ || external_; }

 private:
  // Eigen expressions are callable too: a tag keeps the constant-mass constructor apart
  struct ConstantMass {};
  LagrangianDS(VectorXd position, VectorXd velocity, MatrixXd mass, std::string name, ConstantMass);

  MatrixXd constant_mass_;
  MassFunction mass_function_;
  InternalForce internal_;
  ExternalForce external_;
  mutable VectorXd scratch_;  // F_int, so force() allocates nothing
};

}  // namespace mimpact::kernel
