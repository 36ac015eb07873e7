#pragma once

#include <Eigen/Dense>

namespace mimpact::kernel {

using Eigen::Index;
using Eigen::RowVectorXd;
using Eigen::VectorXd;

// The normal gap of a unilateral contact, g(q) >= 0, as a function of the stacked
// coordinates q of the interaction's systems (the first system's, then the second's).
// Its gradient is the column W_j of the contact; u = W_j^T v is the normal relative velocity
// (u < 0 approaching), and the acceleration of the gap is W_j^T q'' + (dW_j/dt)^T v.
class Relation {
 public:
  virtual ~Relation() = default;
  virtual double gap(const VectorXd& q) const = 0;
  // dg/dq into `row`, already of size q.size().
  virtual void jacobian(const VectorXd& q, RowVectorXd& row) const = 0;
  // (dW/dt)^T v = v^T (d^2 g / dq^2) v, the part of the gap's acceleration that does not
  // depend on q''.
  virtual double jacobian_rate(const VectorXd& q, const VectorXd& v) const = 0;
  // True when W is constant: the contact geometry does not change with q.
  virtual bool is_linear() const = 0;
  // A contact that can rub (docs/model.md, section 16) has tangent directions: 1 in the plane,
  // 2 in space; 0 (the default) a frictionless one. Row r of `rows`, already tangent_rows() x
  // q.size(), is the gradient of the contact points' relative slip along tangent r at q:
  // s_r = rows.row(r) v, lever arms included.
  virtual int tangent_rows() const { return 0; }
  virtual void tangent_jacobian(const VectorXd& q, Eigen::MatrixXd& rows) const {
    (void)q;
    (void)rows;
  }
  // (dW_t/dt)^T v per tangent row into `rates` (already tangent_rows() long): the part of the
  // slip's acceleration that does not depend on q''. By default a central difference of the
  // tangent rows along v, with a step of sqrt(machine epsilon) relative to q.
  virtual void tangent_rates(const VectorXd& q, const VectorXd& v, VectorXd& rates) const;
};

}  // namespace mimpact::kernel
