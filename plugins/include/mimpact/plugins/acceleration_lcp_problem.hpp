#pragma once

#include <memory>

#include "mimpact/common/fields.hpp"
#include "mimpact/kernel/one_step_ns_problem.hpp"
#include "mimpact/numerics/lemke.hpp"

namespace mimpact::plugins {

using kernel::Index;
using kernel::VectorXd;
class ContactDynamics;

// Which persistent contacts stay closed, and with what force: the LCP
// 0 <= lambda _|_ g'' = H lambda + b >= 0 over the persistent contacts (Nguyen & Brogliato 2011,
// eqs. 21-26), solved by Lemke's method. When every free gap acceleration b_j >= 0 the answer is
// lambda = 0 and no LCP is built. Registered as "acceleration-lcp".
class AccelerationLcpProblem : public kernel::ContactForceProblem {
 public:
  using Options = numerics::LemkeOptions;
  // Throws InvalidInput naming an option out of range.
  explicit AccelerationLcpProblem(numerics::LemkeOptions options = {});
  ~AccelerationLcpProblem() override;

  std::string_view name() const override { return "acceleration-lcp"; }
  // Any law: holding a closed contact does not depend on the impact law.
  void check_law(const kernel::NonSmoothLaw&, const std::string&) const override {}
  kernel::ContactForces solve(const kernel::NonSmoothDynamicalSystem& system,
                              std::span<const Index> persistent, double time, const VectorXd& q,
                              const VectorXd& v) override;

  // LCPs actually handed to Lemke (not counting the ones answered by b >= 0).
  std::int64_t lcp_count() const { return lcp_count_; }

 private:
  numerics::LemkeOptions options_;
  std::unique_ptr<ContactDynamics> dynamics_;
  const kernel::NonSmoothDynamicalSystem* initialized_for_ = nullptr;
  std::int64_t lcp_count_ = 0;
};

}  // namespace mimpact::plugins
