#include "mimpact/kernel/relation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mimpact::kernel {

void Relation::tangent_rates(const VectorXd& q, const VectorXd& v, VectorXd& rates) const {
  rates.setZero();
  const double speed = v.norm();
  if (tangent_rows() == 0 || speed == 0.0) return;
  const double step = std::sqrt(std::numeric_limits<double>::epsilon()) *
                      std::max(1.0, q.cwiseAbs().maxCoeff()) / speed;
  Eigen::MatrixXd ahead(tangent_rows(), q.size()), behind(tangent_rows(), q.size());
  tangent_jacobian(q + step * v, ahead);
  tangent_jacobian(q - step * v, behind);
  rates = (ahead - behind) * v / (2.0 * step);
}

}  // namespace mimpact::kernel
