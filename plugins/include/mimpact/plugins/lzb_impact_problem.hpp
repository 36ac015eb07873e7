#pragma once

#include <string_view>

#include "mimpact/kernel/one_step_ns_problem.hpp"
#include "mimpact/numerics/delassus.hpp"
#include "mimpact/numerics/impact_integrator.hpp"
#include "mimpact/plugins/lzb_impact_options.hpp"

namespace mimpact::plugins {

// The multiple impact among closed contacts with LZB laws: H = W_c^T M^-1 W_c assembled over
// the closed contacts (M factorized by CHOLMOD when it is not diagonal), the LZB impulse
// integration, and v+ = v- + M^-1 W_c P. With friction (a law's friction > 0, its relation's
// tangent rows W_t) the operator of [W_c W_t] and v+ = v- + M^-1 (W_c P + W_t P_t)
// (docs/model.md, section 16). Registered as "lzb".
class LzbImpactProblem : public kernel::ImpactProblem {
 public:
  using Options = LzbImpactOptions;
  // Throws InvalidInput naming an option out of range or of an integrator not chosen
  // (LzbImpactOptions::check).
  explicit LzbImpactProblem(LzbImpactOptions options = {});

  std::string_view name() const override { return "lzb"; }
  void check_law(const kernel::NonSmoothLaw& law, const std::string& which) const override;
  kernel::ImpactReport solve(kernel::NonSmoothDynamicalSystem& system,
                             std::span<const kernel::Index> closed, double time) override;

  // Sees the samples of every impact solved from now on (none when null), the interactions
  // of options().impulse_steps.sampled_contacts among them (all when none is).
  void set_impact_observer(numerics::ImpactObserver* observer) override { observer_ = observer; }
  const LzbImpactOptions& options() const { return options_; }

 private:
  void solve_with_friction(const kernel::NonSmoothDynamicalSystem& system,
                           std::span<const kernel::Index> closed, const Eigen::VectorXd& q,
                           const Eigen::SparseMatrix<double>& W, numerics::ImpactObserver* observer,
                           kernel::ImpactReport& report);

  LzbImpactOptions options_;
  std::unique_ptr<numerics::ImpactIntegrator> integrator_;
  std::vector<numerics::ContactLaw> laws_;
  numerics::ImpactObserver* observer_ = nullptr;
};

}  // namespace mimpact::plugins
