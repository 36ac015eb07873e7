#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mimpact/common/fields.hpp"
#include "mimpact/numerics/contact_law.hpp"
#include "mimpact/numerics/impact_integrator.hpp"
#include "mimpact/numerics/impact_observer.hpp"
#include "mimpact/numerics/impulse_step_friction.hpp"
#include "mimpact/numerics/impulse_step_integrator.hpp"
#include "mimpact/numerics/lzb_options.hpp"

namespace mimpact::numerics {

// The LZB (Liu-Zhao-Brogliato) multiple-impact law integrated in the principal impulse:
// Darboux-Keller dynamics du = H dP with H = W^T M^-1 W frozen, per-contact compliance and
// energetic restitution, the distributing law dP_j / dP_pi = F_j / F_pi and the time
// recovered from dt = dP_pi / F_pi (docs/model.md, sections 2-6; Nguyen & Brogliato, INRIA RR-7636,
// 2011, algorithms 1-3; Liu, Zhao & Brogliato, Proc. R. Soc. A 464, 2008).
//
// Four departures from the paper, each keeping its convergence and removing a failure:
// - The primary contact is the one with the largest force, a contact entering compression
//   counting with the force it would have as primary. With equal laws this is the paper's
//   choice (largest energy, or most negative velocity when none is stored); unlike it, no
//   contact ever steps more than delta_p, so a tiny primary energy late in a dissipative
//   impact cannot make a re-entering contact's step explode.
// - A contact takes part while E_j > tol_E_j or u_j < -tol_u_j (LzbOptions), tolerances
//   that vanish with delta_p; the impact ends when none does. A fixed threshold either
//   distorts the forces (large) or never lets a dissipative impact end (tiny).
// - A step ends where the primary's phase ends inside it (u_pi crossing 0, E_pi reaching its
//   release level): a lone contact comes out exact at any delta_p, and an elastic chain
//   keeps its energy to second order.
// - dt is the integral of dP / F over the primary's step with E linear in P, exact for the
//   power law where a contact starts or ends (F -> 0), where the paper's dt = delta_p / F
//   converges only as delta_p^0.4.
//
// With sparse H the work of a step is proportional to the contacts taking part (about the
// width of the wave in a chain), not to all contacts. The step loop allocates nothing;
// buffers are reused from one call to the next.
class LzbImpulseIntegrator : public ImpulseStepIntegrator {
 public:
  explicit LzbImpulseIntegrator(LzbOptions options = {});

  std::string_view name() const override { return "impulse-step"; }
  // Coulomb friction at the contacts with tangential rows, a first-order step in delta_p
  // (ImpulseStepFriction).
  bool integrates_friction() const override { return true; }

 protected:
  void take_steps(const Input& input, ImpactObserver* observer, ImpactResult& result) override;

 private:
  // the step loop, its frictional stage compiled in only where the impact has friction
  template <bool Frictional, class Delassus>
  void step(const Delassus& H, const LawConstants* law, ImpactObserver* observer,
            ImpactResult& result);
  void prepare(const Eigen::VectorXd& diagonal, const Eigen::VectorXd& u_minus,
               const LawTable& laws);
  void notify(ImpactObserver* observer, std::int64_t step, double time, double principal);

  // per contact, reused from impact to impact: the step loop allocates nothing
  struct Contacts {
    std::vector<double> tolerance_u, tolerance_energy;  // the thresholds of taking part
    std::vector<double> u, u_old, energy, impulse, step_impulse, force, force_hat;
    std::vector<double> impulse_carry;  // the low-order bits the sum of impulse has lost
    std::vector<double> compression_work, max_force, time_of_max, work;
    std::unique_ptr<bool[]> in_impact;  // flag_capacity entries
    std::size_t flag_capacity = 0;
    std::vector<Eigen::Index> active;        // contacts taking part, the first ones listed
    std::vector<Eigen::Index> merge_buffer;  // where contacts that join are merged in order
  };

  Contacts contacts_;
  std::size_t initially_active_ = 0;  // how many take part at the start
  Eigen::MatrixXd dense_;             // H, for impacts among few contacts
  ImpulseStepFriction friction_;      // the tangential impulses, where a contact has friction
};

}  // namespace mimpact::numerics
