#pragma once

#include "mimpact/common/fields.hpp"
#include "mimpact/kernel/one_step_ns_problem.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace mimpact::plugins {

struct LzbImpactOptions {
  // The impulse-step integrator's options; its sampled_contacts are interactions of the system.
  numerics::LzbOptions integrator;
  // When > 0, each impact takes delta_p = relative_delta_p * max_j |u_j-| / H_jj, this
  // share of its natural impulse (the impulse that stops its fastest contact alone), instead
  // of integrator.delta_p: impacts of very different strengths (a ball's shrinking bounces)
  // are then resolved alike.
  double relative_delta_p = 0.0;
  // Impacts among at most this many contacts use a dense H; larger ones a sparse H, whose
  // steps cost in proportion to the contacts taking part.
  Eigen::Index dense_up_to = 16;

  // The integrator's fields are the problem's own: {"delta_p": 1e-6, "relative_delta_p": ...}.
  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    numerics::LzbOptions::visit_fields(self.integrator, field);
    field("relative_delta_p", self.relative_delta_p,
          within(0.0, 1.0, "0 for off, else a share of the natural impulse", false, true));
    field("dense_up_to", self.dense_up_to, within(0, 2147483648.0));
  }
};

// The multiple impact among closed contacts with LZB laws: H = W_c^T M^-1 W_c assembled over
// the closed contacts (M factorized by CHOLMOD when it is not diagonal), the LZB impulse
// integration, and v+ = v- + M^-1 W_c P. Registered as "lzb".
class LzbImpactProblem : public kernel::ImpactProblem {
 public:
  using Options = LzbImpactOptions;
  // Throws InvalidInput naming an option out of range.
  explicit LzbImpactProblem(LzbImpactOptions options = {});

  std::string_view name() const override { return "lzb"; }
  void check_law(const kernel::NonSmoothLaw& law, const std::string& which) const override;
  kernel::ImpactReport solve(kernel::NonSmoothDynamicalSystem& system,
                             std::span<const kernel::Index> closed, double time) override;

  // Sees the impulse steps of every impact solved from now on (none when null), the
  // interactions of options().integrator.sampled_contacts among them (all when none is).
  void set_impact_observer(numerics::ImpactObserver* observer) override { observer_ = observer; }
  const LzbImpactOptions& options() const { return options_; }

 private:
  LzbImpactOptions options_;
  numerics::LzbImpulseIntegrator integrator_;
  std::vector<numerics::ContactLaw> laws_;
  numerics::ImpactObserver* observer_ = nullptr;
};

}  // namespace mimpact::plugins
