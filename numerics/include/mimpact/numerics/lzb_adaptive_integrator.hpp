#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "mimpact/common/fields.hpp"
#include "mimpact/numerics/contact_law.hpp"
#include "mimpact/numerics/impact_integrator.hpp"
#include "mimpact/numerics/impact_observer.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace mimpact::numerics {

struct LzbAdaptiveOptions {
  // below 1e-13 double precision cannot meet the tolerance
  static constexpr Allowed kToleranceRange =
      within(1e-13, 0.1)
          .described("1e-13 <= tolerance <= 0.1 (below 1e-13 double precision cannot meet it)");

  // The relative accuracy asked of the result. With V the fastest pre-impact approach,
  // |u-|max, the velocities are to be right to tolerance * V, and each contact's impulse and
  // indentation to the same fraction of its natural ones (V / H_jj, and the indentation that
  // stores V^2 / (2 H_jj)); each step's local error is held to a share of that, so that the
  // steps' errors add up to about the tolerance. A contact joins the impact once it approaches
  // faster than tolerance * V, and the impact ends when no contact approaches faster and none holds
  // more than (tolerance * V)^2 / (2 H_jj): the same rule as the impulse steps' with
  // tolerance * V in place of a fraction of H_jj delta_p.
  double tolerance = 1e-8;
  // The impact is abandoned (status step_limit) after this many steps and restarts.
  std::int64_t max_steps = 100'000'000;
  // The observer sees the state every this long (s) of the impact; 0: the start and the end.
  double sample_interval = 0.0;
  // An impact whose laws are continuous at its switches (e = 1, or bi-stiffness with e > 0)
  // keeps them within its steps while at least this many contacts hold energy or approach, until
  // fewer than half as many do; otherwise each switch is located and ends a step of all the
  // contacts, whose switches grow with them (a packing's impact then costs as the square of its
  // contacts). Kept within, a switch costs nothing of its own, and the steps are those the
  // released forces' error allows: the cheaper where many contacts switch, the dearer where few
  // do (docs/design/adaptive_lzb.md: on hexagonal packings locating is the cheaper below about
  // 128). 1: always within the steps; more than the impact's contacts: always located.
  std::int64_t within_steps_from = 128;
  // Contacts the observer sees (empty: all of them), until set_sampled_contacts changes them.
  std::vector<Eigen::Index> sampled_contacts;

  template <class Self, class Visit>
  static void visit_fields(Self& self, Visit&& field) {
    field("tolerance", self.tolerance, kToleranceRange);
    field("max_steps", self.max_steps, at_least(1));
    field("sample_interval", self.sample_interval, at_least(0.0, "s, 0: start and end only"));
    field("within_steps_from", self.within_steps_from, at_least(1, "contacts"));
    field("sampled_contacts", self.sampled_contacts, at_least(0, "contact indices"));
  }
};

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
// settled after the step, the contact's impulse integrated again from the turn (Gauss-Legendre
// on the dense output), turns narrowed on the contact's own column of H. A step's work is then
// the members', and the steps those the forces' smoothness allows (docs/design/adaptive_lzb.md).
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

 protected:
  void run(const Input& input, ImpactObserver* observer, LzbResult& result) override;

 private:
  class Impact;  // the state of one impact, its buffers reused from one impact to the next

  LzbAdaptiveOptions options_;
  std::unique_ptr<Impact> impact_;
};

}  // namespace mimpact::numerics
