#pragma once

#include "mimpact/kernel/relation.hpp"

namespace mimpact::kernel {

// A linear time-invariant relation, g = C q + e (C a constant row), with constant tangent rows
// T (0, 1 or 2 of them, each of C's size) when it can rub (Relation::tangent_jacobian).
class LinearRelation : public Relation {
 public:
  // Throws InvalidInput for more than 2 tangent rows or rows of another size than C.
  LinearRelation(RowVectorXd C, double e, Eigen::MatrixXd tangents = {});

  double gap(const VectorXd& q) const override { return C_.dot(q) + e_; }
  void jacobian(const VectorXd&, RowVectorXd& row) const override { row = C_; }
  double jacobian_rate(const VectorXd&, const VectorXd&) const override { return 0.0; }
  bool is_linear() const override { return true; }
  int tangent_rows() const override { return int(T_.rows()); }
  void tangent_jacobian(const VectorXd&, Eigen::MatrixXd& rows) const override { rows = T_; }
  void tangent_rates(const VectorXd&, const VectorXd&, VectorXd& rates) const override {
    rates.setZero();
  }

 private:
  RowVectorXd C_;
  double e_;
  Eigen::MatrixXd T_;
};

}  // namespace mimpact::kernel
