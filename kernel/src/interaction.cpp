#include "mimpact/kernel/interaction.hpp"

#include "mimpact/common/error.hpp"

namespace mimpact::kernel {

Interaction::Interaction(std::shared_ptr<DynamicalSystem> first,
                         std::shared_ptr<DynamicalSystem> second,
                         std::shared_ptr<Relation> relation, std::shared_ptr<NonSmoothLaw> law,
                         std::string name)
    : first_(std::move(first)),
      second_(std::move(second)),
      relation_(std::move(relation)),
      law_(std::move(law)),
      name_(std::move(name)) {
  const std::string which = "interaction '" + name_ + "'";
  if (!first_) throw InvalidInput(which + " has no dynamical system");
  if (!relation_) throw InvalidInput(which + " has no relation");
  if (!law_)
    throw InvalidInput(which +
                       " has no nonsmooth law; allowed: a law the impact "
                       "problem handles, e.g. plugins::LzbLaw");
  if (second_ == first_) throw InvalidInput(which + " joins a system to itself");
  dimension_ = first_->dimension() + (second_ ? second_->dimension() : 0);
  VectorXd q(dimension_);
  stack(first_->position(), second_ ? second_->position() : VectorXd(), q);
  RowVectorXd row;
  checked_jacobian(q, row);
}

Interaction::Interaction(std::shared_ptr<DynamicalSystem> first, std::shared_ptr<Relation> relation,
                         std::shared_ptr<NonSmoothLaw> law, std::string name)
    : Interaction(std::move(first), nullptr, std::move(relation), std::move(law), std::move(name)) {
}

void Interaction::stack(const VectorXd& first, const VectorXd& second, VectorXd& stacked) const {
  stacked.head(first_->dimension()) = first;
  if (second_) stacked.tail(second_->dimension()) = second;
}

void Interaction::checked_jacobian(const VectorXd& q, RowVectorXd& row) const {
  if (row.size() != dimension_) row.resize(dimension_);
  relation_->jacobian(q, row);
  if (row.size() != dimension_)
    throw InvalidInput(
        "interaction '" + name_ + "': the Jacobian has " + std::to_string(row.size()) +
        " entries; allowed: " + std::to_string(dimension_) + " (the coordinates of its systems)");
}

double Interaction::gap() const {
  VectorXd q(dimension_);
  stack(first_->position(), second_ ? second_->position() : VectorXd(), q);
  return relation_->gap(q);
}

double Interaction::velocity() const {
  VectorXd q(dimension_), v(dimension_);
  stack(first_->position(), second_ ? second_->position() : VectorXd(), q);
  stack(first_->velocity(), second_ ? second_->velocity() : VectorXd(), v);
  RowVectorXd row;
  checked_jacobian(q, row);
  return row.dot(v);
}

}  // namespace mimpact::kernel
