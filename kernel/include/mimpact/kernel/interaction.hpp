#pragma once

#include <memory>
#include <string>

#include "mimpact/kernel/dynamical_system.hpp"
#include "mimpact/kernel/non_smooth_law.hpp"
#include "mimpact/kernel/relation.hpp"

namespace mimpact::kernel {

// A unilateral contact between one system and the ground, or between two systems: the
// relation gives its gap, the law what happens when it closes.
class Interaction {
 public:
  // Throws InvalidInput, naming the interaction, when a system, the relation or the law is
  // missing, or when the relation's Jacobian at the systems' positions has the wrong size.
  Interaction(std::shared_ptr<DynamicalSystem> first, std::shared_ptr<DynamicalSystem> second,
              std::shared_ptr<Relation> relation, std::shared_ptr<NonSmoothLaw> law,
              std::string name = "");
  // A contact with the ground (or any fixed obstacle).
  Interaction(std::shared_ptr<DynamicalSystem> first, std::shared_ptr<Relation> relation,
              std::shared_ptr<NonSmoothLaw> law, std::string name = "");

  const std::string& name() const { return name_; }
  // size of the stacked coordinates the relation sees
  Index dimension() const { return dimension_; }
  const std::shared_ptr<DynamicalSystem>& first() const { return first_; }
  const std::shared_ptr<DynamicalSystem>& second() const { return second_; }  // may be null
  const Relation& relation() const { return *relation_; }
  const NonSmoothLaw& law() const { return *law_; }

  // Gap and relative normal velocity at the systems' current state.
  double gap() const;
  double velocity() const;

  // Stacks the coordinates of the systems into `stacked` (already of size dimension()).
  void stack(const VectorXd& first, const VectorXd& second, VectorXd& stacked) const;

  // Evaluates the Jacobian into `row` (resized to dimension() if needed) and throws
  // InvalidInput when the relation hands back a row of another size.
  void checked_jacobian(const VectorXd& q, RowVectorXd& row) const;

 private:
  std::shared_ptr<DynamicalSystem> first_, second_;
  std::shared_ptr<Relation> relation_;
  std::shared_ptr<NonSmoothLaw> law_;
  std::string name_;
  Index dimension_ = 0;
};

}  // namespace mimpact::kernel
