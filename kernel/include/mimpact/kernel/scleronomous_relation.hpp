#pragma once

#include <functional>

#include "mimpact/kernel/relation.hpp"

namespace mimpact::kernel {

// A nonlinear relation that does not depend on time, g = h(q), given by callables. The
// Jacobian callable writes into a row already of size q.size(); the rate callable gives
// v^T (d^2 h / dq^2) v. Without one, the rate is a central difference of the Jacobian along
// v, with a step of sqrt(machine epsilon) relative to q.
class ScleronomousRelation : public Relation {
 public:
  using Gap = std::function<double(const VectorXd& q)>;
  using Jacobian = std::function<void(const VectorXd& q, RowVectorXd& row)>;
  using Rate = std::function<double(const VectorXd& q, const VectorXd& v)>;

  ScleronomousRelation(Gap gap, Jacobian jacobian, Rate rate = {});

  double gap(const VectorXd& q) const override { return gap_(q); }
  void jacobian(const VectorXd& q, RowVectorXd& row) const override { jacobian_(q, row); }
  double jacobian_rate(const VectorXd& q, const VectorXd& v) const override;
  bool is_linear() const override { return false; }

 private:
  Gap gap_;
  Jacobian jacobian_;
  Rate rate_;
  mutable VectorXd shifted_;  // finite-difference workspace
  mutable RowVectorXd ahead_, behind_;
};

}  // namespace mimpact::kernel
