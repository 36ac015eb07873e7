#include "mimpact/kernel/linear_relation.hpp"

#include <string>

#include "mimpact/common/error.hpp"

namespace mimpact::kernel {

LinearRelation::LinearRelation(RowVectorXd C, double e, Eigen::MatrixXd tangents)
    : C_(std::move(C)), e_(e), T_(std::move(tangents)) {
  if (T_.size() == 0) {
    T_.resize(0, C_.size());
    return;
  }
  if (T_.rows() > 2)
    throw InvalidInput(invalid_value_message("a linear relation's tangent rows", double(T_.rows()),
                                             "0, 1 (a tangent in the plane) or 2 (in space)"));
  if (T_.cols() != C_.size())
    throw InvalidInput("a linear relation's tangent rows have " + std::to_string(T_.cols()) +
                       " entries; allowed: " + std::to_string(C_.size()) + ", as C");
}

}  // namespace mimpact::kernel
