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
  // writes the tangent rows (tangent_rows() x q.size(), already sized)
  using Tangents = std::function<void(const VectorXd& q, Eigen::MatrixXd& rows)>;
  // writes (dW_t/dt)^T v per tangent row (already sized)
  using TangentRates = std::function<void(const VectorXd& q, const VectorXd& v, VectorXd& rates)>;

  ScleronomousRelation(Gap gap, Jacobian jacobian, Rate rate = {});

  double gap(const VectorXd& q) const override { return gap_(q); }
  void jacobian(const VectorXd& q, RowVectorXd& row) const override { jacobian_(q, row); }
  double jacobian_rate(const VectorXd& q, const VectorXd& v) const override;
  bool is_linear() const override { return false; }
  // The contact's tangent directions (Relation::tangent_jacobian): `rows` of them (1 or 2),
  // given by `tangents`, with their rates (Relation::tangent_rates) by `rates` or, without, by a
  // central difference. Throws InvalidInput for another count or an empty callable.
  void set_tangents(int rows, Tangents tangents, TangentRates rates = {});
  int tangent_rows() const override { return tangent_rows_; }
  void tangent_jacobian(const VectorXd& q, Eigen::MatrixXd& rows) const override {
    tangents_(q, rows);
  }
  void tangent_rates(const VectorXd& q, const VectorXd& v, VectorXd& rates) const override {
    if (!tangent_rates_) return Relation::tangent_rates(q, v, rates);
    tangent_rates_(q, v, rates);
  }

 private:
  Gap gap_;
  Jacobian jacobian_;
  Rate rate_;
  int tangent_rows_ = 0;
  Tangents tangents_;
  TangentRates tangent_rates_;
  mutable VectorXd shifted_;  // finite-difference workspace
  mutable RowVectorXd ahead_, behind_;
};

}  // namespace mimpact::kernel
