#pragma once

#include "mimpact/kernel/relation.hpp"

namespace mimpact::kernel {

// A linear time-invariant relation, g = C q + e (C a constant row).
class LinearRelation : public Relation {
 public:
  LinearRelation(RowVectorXd C, double e) : C_(std::move(C)), e_(e) {}

  double gap(const VectorXd& q) const override { return C_.dot(q) + e_; }
  void jacobian(const VectorXd&, RowVectorXd& row) const override { row = C_; }
  double jacobian_rate(const VectorXd&, const VectorXd&) const override { return 0.0; }
  bool is_linear() const override { return true; }

 private:
  RowVectorXd C_;
  double e_;
};

}  // namespace mimpact::kernel
