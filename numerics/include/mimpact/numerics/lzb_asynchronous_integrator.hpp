#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <cstdint>
#include <span>
#include <vector>

#include "mimpact/numerics/contact_law.hpp"
#include "mimpact/numerics/impact_integrator.hpp"
#include "mimpact/numerics/impact_observer.hpp"
#include "mimpact/numerics/impulse_step_integrator.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"
#include "mimpact/numerics/lzb_options.hpp"

namespace mimpact::numerics {

// The LZB impact by asynchronous steps (docs/model.md, section 14), as an asynchronous
// variational integrator (Lew, Marsden, Ortiz & West, IJNME 60, 2004) of the LZB flow in time:
// each contact kicks its beads at its own pace, and between kicks everything drifts exactly.
//
// The model is that of LzbImpulseIntegrator: the same laws, states and thresholds, the same
// continuous limit. In time, Darboux-Keller's dP_j = F_j dt with F_j = c E_j^a and
// dE_j = -f u_j dP_j (f = 1 in compression and for mono-stiffness, 1/e^2 in bi-stiffness
// expansion) make w_j = E_j^(1 - a) grow linearly in t while u_j is constant:
// dw_j/dt = -(1 - a) c f u_j. Here u changes only at kicks, so between them each contact's
// energy and the impulse it absorbs (the energy gained over -f u_j) are integrated exactly,
// ends of compression and releases included.
//
// A kick of contact j at t_k applies to u (u += H e_j dP) the impulse it absorbed since its
// last kick, less the share applied ahead then, plus F_j(t_k) h_k / 2 ahead for the step
// h_k = delta_p / F_j now beginning: half of each step's impulse reaches the beads at its start
// and the rest at its end, so the beads' velocities are centred on the step as in Stormer-
// Verlet. The impulses applied add up exactly to those absorbed, so momentum is conserved at
// round-off. A step carries delta_p, or less where the contact holds little energy (at most
// half its natural impulse, Stormer-Verlet's stability bound), ends where an expansion releases
// the contact, and lasts at most kNeighbourRatio times its neighbours' steps.
//
// Why: in a packing the wake behind the front stays loaded with forces far below the front's.
// The synchronous steps update every loaded contact at every step of the strongest; here a
// contact costs in proportion to the impulse it carries, about P_j / delta_p kicks, which
// follows the contacts the wave reaches. In `ImpactResult`, `steps` and `contact_steps` both
// count kicks, and the observer's principal_impulse is the sum of all impulses.
class LzbAsynchronousIntegrator : public ImpulseStepIntegrator {
 public:
  // The options of LzbImpulseIntegrator; sample_every counts kicks.
  explicit LzbAsynchronousIntegrator(LzbOptions options = {});

  std::string_view name() const override { return "asynchronous"; }

  // The state of one contact. u lives apart: neighbours' kicks write it.
  struct Contact {
    // constants of the impact: H_jj (1/kg) and the thresholds of taking part
    double h_jj = 0.0, tolerance_u = 0.0, tolerance_energy = 0.0;
    double energy = 0.0, w = 0.0;  // E (J) and w = E^(1 - a), kept together
    double release_w = 0.0;        // w where an expansion releases the contact
    double clock = 0.0;            // up to when energy, absorbed and work are integrated (s)
    double absorbed = 0.0;         // impulse absorbed since the last kick (N s)
    double ahead = 0.0;            // impulse applied ahead at the last kick (N s)
    double pace = 0.0;             // the running step's length (s); infinite when unloaded
    double impulse = 0.0, impulse_carry = 0.0;  // P applied (N s), its Kahan carry
    double compression_work = 0.0, work = 0.0;  // J
    double max_force = 0.0, time_of_max = 0.0;  // N, s
    double due = 0.0;                           // the next kick (s)
    std::uint32_t stamp = 0;  // the stamp of its due kick: queued kicks with another are stale
    bool in_impact = false;
  };
  // A contact's kick, due at `time`.
  struct Step {
    double time;
    std::uint32_t contact, stamp;
  };

 protected:
  void take_steps(const Input& input, ImpactObserver* observer, ImpactResult& result) override;

 private:
  template <class Delassus>
  void kicks(const Delassus& H, ImpactObserver* observer, ImpactResult& result);
  void prepare(const Eigen::VectorXd& diagonal, const Eigen::VectorXd& u_minus,
               const LawTable& laws);
  void drift(Eigen::Index j, double time);
  template <class Delassus>
  void kick(const Delassus& H, Eigen::Index j, double time);
  template <class Delassus>
  void apply_impulse(const Delassus& H, Eigen::Index j, double dp, double time);
  template <class Delassus>
  void join(const Delassus& H, Eigen::Index j, double time);
  template <class Delassus>
  double neighbour_limit(const Delassus& H, Eigen::Index j) const;
  template <class Delassus>
  void tighten_neighbours(const Delassus& H, Eigen::Index j, double time);
  double step_length(Eigen::Index j, double limit) const;
  void set_release_level(Eigen::Index i);
  void schedule(Eigen::Index j, double due);
  void notify(ImpactObserver* observer, std::int64_t steps, double time);

  const LawConstants* laws_ = nullptr;  // the law table of the impact being integrated
  std::vector<Contact> contacts_;
  std::vector<double> u_;
  std::vector<Step> queue_;  // a binary min-heap on (time, contact)
  double impulse_sum_ = 0.0;
  Eigen::MatrixXd dense_;  // H, for impacts among few contacts
};

}  // namespace mimpact::numerics
