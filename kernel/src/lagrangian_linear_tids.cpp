#include "mimpact/kernel/lagrangian_linear_tids.hpp"

#include "mimpact/common/error.hpp"

namespace mimpact::kernel {

namespace {

void expect_square(const std::string& system, const char* what, const MatrixXd& matrix,
                   Index dimension, bool optional) {
  if (optional && matrix.size() == 0) return;
  if (matrix.rows() != dimension || matrix.cols() != dimension)
    throw InvalidInput("system '" + system + "': " + what + " is " + std::to_string(matrix.rows()) +
                       "x" + std::to_string(matrix.cols()) +
                       "; allowed: " + std::to_string(dimension) + "x" + std::to_string(dimension));
  if (!matrix.allFinite())
    throw InvalidInput("system '" + system + "': " + what + " has a NaN or infinite entry");
}

}  // namespace

LagrangianLinearTIDS::LagrangianLinearTIDS(VectorXd position, VectorXd velocity, Matrices matrices,
                                           std::string name)
    : DynamicalSystem(std::move(position), std::move(velocity), std::move(name)),
      matrices_(std::move(matrices)) {
  expect_square(this->name(), "the mass matrix", matrices_.mass, dimension(), false);
  expect_square(this->name(), "the stiffness matrix K", matrices_.stiffness, dimension(), true);
  expect_square(this->name(), "the damping matrix C", matrices_.damping, dimension(), true);
  const VectorXd& f = matrices_.external_force;
  if (f.size() != 0 && (f.size() != dimension() || !f.allFinite()))
    throw InvalidInput("system '" + this->name() + "': F_ext has " + std::to_string(f.size()) +
                       " entries; allowed: " + std::to_string(dimension()) + " finite values");
  diagonal_ = matrices_.mass.isDiagonal(0.0);
}

void LagrangianLinearTIDS::mass(const VectorXd&, MatrixXd& mass) const { mass = matrices_.mass; }

void LagrangianLinearTIDS::force(double, const VectorXd& q, const VectorXd& v,
                                 VectorXd& force) const {
  if (matrices_.external_force.size()) {
    force = matrices_.external_force;
  } else {
    force.setZero();
  }
  if (matrices_.stiffness.size()) force.noalias() -= matrices_.stiffness * q;
  if (matrices_.damping.size()) force.noalias() -= matrices_.damping * v;
}

bool LagrangianLinearTIDS::has_force() const {
  return matrices_.stiffness.size() || matrices_.damping.size() ||
         (matrices_.external_force.size() && !matrices_.external_force.isZero(0.0));
}

}  // namespace mimpact::kernel
