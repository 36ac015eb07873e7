#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "mimpact/numerics/contact_law.hpp"
#include "mimpact/numerics/impact_integrator.hpp"
#include "mimpact/numerics/impact_observer.hpp"
#include "mimpact/numerics/lzb_adaptive_options.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace mimpact::numerics {

namespace adaptive_lzb {
class Impact;  // the state of one impact (src/lzb_adaptive_impact.hpp)
}

// The LZB impact integrated as its continuous limit (docs/model.md, section 10): per contact
// the energy coordinate delta_j, with dP_j/dt = K_j delta_j^eta_j and du/dt = H dP/dt, by
// Dormand-Prince 5(4) with error control (Odeint's controller) to LzbAdaptiveOptions::tolerance.
// The same model as the impulse steps of LzbImpulseIntegrator (mono- and bi-stiffness, any
// eta, e from 0 to 1, LZB's re-loading rule), without their first-order error in delta_p:
// every switch of the right-hand side (a contact joins, its compression ends, it re-loads, it
// is released) is located on the dense output to machine precision, and the integration
// restarts there, so that the method keeps its fifth order.
//
// The ODE carries only the contacts holding energy; the contacts they push (their neighbours
// through H) are watched for joining, and every other contact costs nothing. The work of a
// step is proportional to the contacts taking part: about the width of the wave in a chain.
//
// Where an impact holds many contacts (a packing's), a located switch would end a step of all
// of them, and the switches grow with them. Where every law is continuous at its switches (e =
// 1, or bi-stiffness with e > 0: d delta_j/dt = -u_j and -u_j / e^2 meet where u_j = 0) they stay
// within the steps: the members (the contacts holding energy or approaching, and two rings of
// their neighbours) all carry delta_j and P_j; a separating contact's delta_j runs below 0,
// its force switching off by itself; where it approaches again, it is set back to grow from 0;
// where an inelastic contact's u_j changes sign its delta_j goes on at the other rate. Both are
// settled after the step, the contact integrated again alone from the turn (Dormand-Prince,
// Boost.Odeint, to the same tolerance), turns narrowed on the contact's own column of H. A step's
// work is then the members', and the steps those the forces' smoothness allows
// (docs/design/adaptive_lzb.md).
class LzbAdaptiveIntegrator : public ImpactIntegrator {
 public:
  explicit LzbAdaptiveIntegrator(LzbAdaptiveOptions options = {});
  ~LzbAdaptiveIntegrator() override;
  LzbAdaptiveIntegrator(LzbAdaptiveIntegrator&&) noexcept;
  LzbAdaptiveIntegrator& operator=(LzbAdaptiveIntegrator&&) noexcept;

  // In the result, `steps` counts the Runge-Kutta steps and `contact_steps` the contacts
  // integrated, summed over them; the observer's principal_impulse is the sum of all impulses.
  std::string_view name() const override { return "adaptive"; }
  const LzbAdaptiveOptions& options() const { return options_; }
  // Changes the tolerance for the next impacts; throws InvalidInput when out of range.
  void set_tolerance(double tolerance);
  // tolerance x V, V the fastest approach: the velocities are right to that
  Eigen::VectorXd velocity_resolution(const Eigen::VectorXd& diagonal,
                                      const Eigen::VectorXd& u_minus) const override;
  // Coulomb friction at the contacts with tangential rows (docs/model.md, "Friction"): slip,
  // stick and their switches located as events, as the normal law's.
  bool integrates_friction() const override;

 protected:
  void run(const Input& input, ImpactObserver* observer, ImpactResult& result) override;

 private:
  using Impact = adaptive_lzb::Impact;  // its buffers reused from one impact to the next

  LzbAdaptiveOptions options_;
  std::unique_ptr<Impact> impact_;
};

}  // namespace mimpact::numerics
