#pragma once

#include "mimpact/kernel/one_step_ns_problem.hpp"
#include "mimpact/kernel/parameters.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace mimpact::plugins {

struct LzbImpactOptions {
  numerics::LzbOptions integrator;
  // When > 0, each impact takes delta_p = relative_delta_p * max_j |u_j-| / H_jj, this
  // share of its natural impulse (the impulse that stops its fastest contact alone), instead
  // of integrator.delta_p: impacts of very different strengths (a ball's shrinking bounces)
  // are then resolved alike.
  double relative_delta_p = 0.0;
  // Impacts among at most this many contacts use a dense H; larger ones a sparse H, whose
  // steps cost in proportion to the contacts taking part.
  Eigen::Index dense_up_to = 16;
};

// The multiple impact among closed contacts with LZB laws: H = W_c^T M^-1 W_c assembled over
// the closed contacts (M factorized by CHOLMOD when it is not diagonal), the LZB impulse
// integration, and v+ = v- + M^-1 W_c P. Registered as "lzb".
class LzbImpactProblem : public kernel::ImpactProblem {
 public:
  explicit LzbImpactProblem(LzbImpactOptions options = {});
  // Reads "delta_p", "relative_delta_p", "termination_velocity_factor", "max_steps",
  // "dense_up_to".
  static std::unique_ptr<kernel::ImpactProblem> create(const kernel::Parameters& parameters);

  std::string_view name() const override { return "lzb"; }
  void check_law(const kernel::NonSmoothLaw& law, const std::string& which) const override;
  kernel::ImpactReport solve(kernel::NonSmoothDynamicalSystem& system,
                             std::span<const kernel::Index> closed, double time) override;

  // Sees the impulse steps of every impact solved from now on (none when null).
  void set_observer(numerics::ImpactObserver* observer) { observer_ = observer; }
  // The full integrator result of the last impact, for what the report leaves out.
  const numerics::LzbResult& last_result() const { return last_; }
  const LzbImpactOptions& options() const { return options_; }

 private:
  LzbImpactOptions options_;
  numerics::LzbImpulseIntegrator integrator_;
  numerics::LzbResult last_;
  std::vector<numerics::ContactLaw> laws_;
  numerics::ImpactObserver* observer_ = nullptr;
};

}  // namespace mimpact::plugins
