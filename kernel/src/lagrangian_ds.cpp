#include "mimpact/kernel/lagrangian_ds.hpp"

#include "mimpact/common/error.hpp"

namespace mimpact::kernel {

namespace {

void expect_size(const std::string& system, const char* what, Index rows, Index cols,
                 Index dimension, Index expected_cols) {
  if (rows != dimension || cols != expected_cols)
    throw InvalidInput("system '" + system + "': " + what + " has size " + std::to_string(rows) +
                       "x" + std::to_string(cols) + "; allowed: " + std::to_string(dimension) +
                       "x" + std::to_string(expected_cols));
}

}  // namespace

LagrangianDS::LagrangianDS(VectorXd position, VectorXd velocity, MatrixXd mass, std::string name,
                           ConstantMass)
    : DynamicalSystem(std::move(position), std::move(velocity), std::move(name)),
      constant_mass_(std::move(mass)) {
  expect_size(this->name(), "the mass matrix", constant_mass_.rows(), constant_mass_.cols(),
              dimension(), dimension());
}

LagrangianDS::LagrangianDS(VectorXd position, VectorXd velocity, MassFunction mass,
                           std::string name)
    : DynamicalSystem(std::move(position), std::move(velocity), std::move(name)),
      mass_function_(std::move(mass)) {
  if (!mass_function_) throw InvalidInput("system '" + this->name() + "': no mass function");
}

void LagrangianDS::mass(const VectorXd& q, MatrixXd& mass) const {
  if (!mass_function_) {
    mass = constant_mass_;
    return;
  }
  mass_function_(q, mass);
  expect_size(name(), "M(q)", mass.rows(), mass.cols(), dimension(), dimension());
}

bool LagrangianDS::mass_is_diagonal() const {
  return !mass_function_ && constant_mass_.isDiagonal(0.0);
}

void LagrangianDS::force(double t, const VectorXd& q, const VectorXd& v, VectorXd& force) const {
  force.setZero();
  if (external_) {
    external_(t, force);
    expect_size(name(), "F_ext(t)", force.rows(), 1, dimension(), 1);
  }
  if (internal_) {
    scratch_.setZero(dimension());
    internal_(t, q, v, scratch_);
    expect_size(name(), "F_int(t, q, v)", scratch_.rows(), 1, dimension(), 1);
    force -= scratch_;
  }
}

}  // namespace mimpact::kernel
