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
};

}  // namespace mimpact::kernel
