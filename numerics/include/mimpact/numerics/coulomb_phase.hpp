#pragma once

#include <array>

// One contact's phase under Coulomb's law with a rigid tangential response (docs/model.md,
// "Friction"), whatever carries it along: the impulse of the adaptive LZB impact, or time in the
// compliant integrator. With the contact's normal force F (or dP_n) and mu F the cone's radius,
// its tangential force f_t (or dP_t) on its rows (one in the plane, two in space) is
//   slip:  f_t = -mu F d, d the slip's direction: s/|s| in space where it turns (Keller 1986),
//          fixed in the plane, and fixed for a slip just started from rest until it has grown
//   stick: the force that keeps ds = 0, while |f_t| <= mu F
// and its switches are events of the integration: a slip stops (then it sticks if the force that
// keeps it is within the cone, else slips the other way: Stronge, Impact Mechanics, 2000), a
// stick ends where that force reaches mu F, a slip from rest grows free of its direction.
namespace mimpact::numerics::coulomb {

// |v| of a contact's 1 or 2 rows
double norm(const double* v, int rows);

struct Phase {
  enum class Mode : unsigned char { choose, slip, stick };
  Mode mode = Mode::choose;
  bool live = false;                  // a slip in space whose d is s/|s|
  bool forced = false;                // its stick ended: it slips where its force points
  bool from_rest = false;             // a slip started from rest (slip_against), not yet grown
  std::array<double, 2> direction{};  // a fixed slip's d

  // A contact new or past a switch (mode choose): slip where |s| > tolerance (m/s), else stick.
  void start(const double* slip, int rows, double tolerance);
  // How far the force x that keeps the contact stuck lies beyond the cone of radius `limit`
  // (infinite once its stick has ended). The caller's active-set rule: the sticking contact
  // furthest outside slips against its force (slip_against), and the forces are found again.
  double excess(const double* x, int rows, double limit) const;
  // Slip with d = -x / |x|: where the force x that kept it stuck would drive it.
  void slip_against(const double* x, int rows);
  // A slipping contact's tangential force f_t = -limit d at slip s.
  void slip_force(double limit, const double* slip, int rows, double* force) const;
  // Two values, > 0 before a switch: the first crosses 0 where its slip stops (a slip from rest:
  // where it has turned back by the tolerance, m/s, since it starts within it) or its stick
  // ends; the second where a slip from rest has grown to 2 tolerance (else it stays 1).
  std::array<double, 2> watched(double limit, const double* slip, const double* force, int rows,
                                double tolerance) const;
  // Past a switch: a stick that ended slips where its force points; otherwise the mode is
  // chosen again from the slip and forces there.
  void pass(bool stick_end) {
    if (stick_end)
      forced = true;
    else
      mode = Mode::choose;
  }
};

// The active-set rule where a segment starts (Stronge 2000: a slip that stops sticks or
// reverses): `refresh()` finds every contact's forces for the phases as they are, and
// `each(visit)` calls visit(phase, force, rows, limit) for every rubbing contact, its force
// (f_t, rows values) and its cone's radius; while some sticking contact's force lies beyond its
// cone, the one furthest beyond slips against its force and the forces are found again.
template <class Refresh, class Each>
void settle_sticks(Refresh&& refresh, Each&& each) {
  while (true) {
    refresh();
    Phase* worst = nullptr;
    const double* worst_force = nullptr;
    int worst_rows = 0;
    double worst_excess = 0.0;
    each([&](Phase& phase, const double* force, int rows, double limit) {
      if (phase.mode != Phase::Mode::stick) return;
      const double excess = phase.excess(force, rows, limit);
      if (excess > worst_excess) {
        worst = &phase;
        worst_force = force;
        worst_rows = rows;
        worst_excess = excess;
      }
    });
    if (!worst) return;
    worst->slip_against(worst_force, worst_rows);
  }
}

}  // namespace mimpact::numerics::coulomb
