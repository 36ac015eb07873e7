#include "mimpact/kernel/dynamical_system.hpp"

#include <sstream>

#include "mimpact/common/error.hpp"

namespace mimpact::kernel {

namespace {

void check_state(const std::string& name, const Eigen::Ref<const VectorXd>& q,
                 const Eigen::Ref<const VectorXd>& v) {
  if (q.size() != v.size())
    throw InvalidInput("system '" + name + "': position has " + std::to_string(q.size()) +
                       " entries and velocity " + std::to_string(v.size()) +
                       "; allowed: equal sizes");
  if (!q.allFinite() || !v.allFinite())
    throw InvalidInput("system '" + name + "': the state has a NaN or infinite entry");
}

}  // namespace

DynamicalSystem::DynamicalSystem(VectorXd position, VectorXd velocity, std::string name)
    : position_(std::move(position)), velocity_(std::move(velocity)), name_(std::move(name)) {
  check_state(name_, position_, velocity_);
  if (position_.size() == 0)
    throw InvalidInput("system '" + name_ + "' has no coordinates; allowed: dimension >= 1");
}

void DynamicalSystem::set_state(const Eigen::Ref<const VectorXd>& position,
                                const Eigen::Ref<const VectorXd>& velocity) {
  if (position.size() != dimension() || velocity.size() != dimension())
    throw InvalidInput("system '" + name_ + "': a state of size " +
                       std::to_string(position.size()) +
                       "; allowed: " + std::to_string(dimension()));
  check_state(name_, position, velocity);
  position_ = position;
  velocity_ = velocity;
}

void DynamicalSystem::check_mass() const {
  MatrixXd M = MatrixXd::Zero(dimension(), dimension());
  mass(position_, M);
  std::ostringstream why;
  if (M.rows() != dimension() || M.cols() != dimension()) {
    why << "M(q) is " << M.rows() << "x" << M.cols() << "; allowed: " << dimension() << "x"
        << dimension();
  } else if (!M.allFinite()) {
    why << "M(q) has a NaN or infinite entry";
  } else if (!M.isApprox(M.transpose(), 1e-12)) {
    why << "M(q) is not symmetric";
  } else if (Eigen::LLT<MatrixXd>(M).info() != Eigen::Success) {
    why << "M(q) is not positive definite (smallest diagonal entry " << M.diagonal().minCoeff()
        << "); allowed: a positive mass";
  } else {
    return;
  }
  throw InvalidInput("system '" + name_ + "': " + why.str());
}

}  // namespace mimpact::kernel
