#include "mimpact/kernel/scleronomous_relation.hpp"

#include <cmath>
#include <limits>

#include "mimpact/common/error.hpp"

namespace mimpact::kernel {

ScleronomousRelation::ScleronomousRelation(Gap gap, Jacobian jacobian, Rate rate)
    : gap_(std::move(gap)), jacobian_(std::move(jacobian)), rate_(std::move(rate)) {
  if (!gap_ || !jacobian_)
    throw InvalidInput("a scleronomous relation needs both a gap and a Jacobian function");
}

void ScleronomousRelation::set_tangents(int rows, Tangents tangents, TangentRates rates) {
  if (rows != 1 && rows != 2)
    throw InvalidInput(invalid_value_message("a relation's tangent rows", double(rows),
                                             "1 (a tangent in the plane) or 2 (in space)"));
  if (!tangents) throw InvalidInput("a relation's tangent rows need a function that gives them");
  tangent_rows_ = rows;
  tangents_ = std::move(tangents);
  tangent_rates_ = std::move(rates);
}

double ScleronomousRelation::jacobian_rate(const VectorXd& q, const VectorXd& v) const {
  if (rate_) return rate_(q, v);
  const double speed = v.norm();
  if (speed == 0.0) return 0.0;
  const double step = std::sqrt(std::numeric_limits<double>::epsilon()) *
                      std::max(1.0, q.cwiseAbs().maxCoeff()) / speed;
  ahead_.resize(q.size());
  behind_.resize(q.size());
  shifted_ = q + step * v;
  jacobian_(shifted_, ahead_);
  shifted_ = q - step * v;
  jacobian_(shifted_, behind_);
  return (ahead_ - behind_).dot(v) / (2.0 * step);
}

}  // namespace mimpact::kernel
