#pragma once

#include <array>
#include <string_view>
#include <utility>

#include "mimpact/common/fields.hpp"
#include "mimpact/kernel/one_step_ns_problem.hpp"
#include "mimpact/numerics/delassus.hpp"
#include "mimpact/numerics/lzb_adaptive_integrator.hpp"
#include "mimpact/numerics/lzb_asynchronous_integrator.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace mimpact::plugins {

// How the LZB impact is integrated: by the impulse steps of Nguyen & Brogliato (2011), first
// order in delta_p; by the same steps taken by each contact at its own pace
// (numerics::LzbAsynchronousIntegrator, for impacts whose loaded contacts far outnumber the
// front's: packings); or by the adaptive integration of their continuous limit to a tolerance
// (numerics::LzbAdaptiveIntegrator).
enum class LzbIntegrator { impulse_step, asynchronous, adaptive };

constexpr auto enum_names(LzbIntegrator) {
  using Name = std::pair<LzbIntegrator, std::string_view>;
  return std::array{Name{LzbIntegrator::impulse_step, "impulse-step"},
                    Name{LzbIntegrator::asynchronous, "asynchronous"},
                    Name{LzbIntegrator::adaptive, "adaptive"}};
}

struct LzbImpactOptions {
  LzbIntegrator integrator = LzbIntegrator::impulse_step;
  // The impulse steps' options, synchronous or asynchronous; max_steps and sampled_contacts
  // (interactions of the system) serve the adaptive integrator too.
  numerics::LzbOptions impulse_steps;
  // The adaptive integrator's options but those two.
  numerics::LzbAdaptiveOptions adaptive;
  // When > 0, each impact takes delta_p = relative_delta_p * max_j |u_j-| / H_jj, this
  // share of its natural impulse (the impulse that stops its fastest contact alone), instead
  // of integrator.delta_p: impacts of very different strengths (a ball's shrinking bounces)
  // are then resolved alike.
  double relative_delta_p = 0.0;
  // Impacts among at most this many contacts use a dense H; larger ones a sparse H, whose
  // steps cost in proportion to the contacts taking part.
  Eigen::Index dense_up_to = 16;

  // The adaptive integrator's options, with max_steps and sampled_contacts from impulse_steps.
  numerics::LzbAdaptiveOptions adaptive_options() const;

  // The integrators' fields are the problem's own: {"integrator": "adaptive", "tolerance":
  // 1e-8} or {"delta_p": 1e-6, "relative_delta_p": ...}.
  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("integrator", self.integrator);
    numerics::LzbOptions::visit_fields(self.impulse_steps, field);
    numerics::LzbAdaptiveOptions::visit_fields(
        self.adaptive, [&](std::string_view name, auto& value, auto&&... allowed) {
          if (name == "tolerance" || name == "sample_interval") field(name, value, allowed...);
        });
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

  // Sees the samples of every impact solved from now on (none when null), the interactions
  // of options().impulse_steps.sampled_contacts among them (all when none is).
  void set_impact_observer(numerics::ImpactObserver* observer) override { observer_ = observer; }
  const LzbImpactOptions& options() const { return options_; }

 private:
  numerics::LzbResult integrate(const numerics::Delassus& delassus, const Eigen::VectorXd& u_minus,
                                numerics::ImpactObserver* observer);

  LzbImpactOptions options_;
  numerics::LzbImpulseIntegrator impulse_steps_;
  numerics::LzbAsynchronousIntegrator asynchronous_;
  numerics::LzbAdaptiveIntegrator adaptive_;
  std::vector<numerics::ContactLaw> laws_;
  numerics::ImpactObserver* observer_ = nullptr;
};

}  // namespace mimpact::plugins
