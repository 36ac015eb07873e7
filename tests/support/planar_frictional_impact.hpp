#pragma once

// The closed form of a planar single-contact impact with Coulomb friction and the energetic
// coefficient of restitution (Stronge, "Rigid body collisions with friction", Proc. R. Soc.
// Lond. A 431, 1990; Impact Mechanics, CUP 2000): the Darboux-Keller dynamics in the normal
// impulse p, piecewise linear between the slip's phases, with the restitution phase ending where
// the normal force has given back e^2 of its compression work. An independent method for the
// integrators: it never integrates, it solves each phase's line.

#include <algorithm>
#include <cmath>
#include <limits>

namespace mimpact::testing {

// The contact's 2 x 2 Delassus operator [H_nn H_nt; H_tn H_tt] (1/kg), its pre-impact normal
// velocity u_n0 < 0 and slip s_0 (m/s), Coulomb's mu and the energetic e.
struct PlanarImpact {
  double h_nn, h_tn, h_tt, u_n0, s_0, mu, e;
};

// The normal and tangential impulses (N s) at the impact's end.
struct PlanarOutcome {
  double p_n = 0.0, p_t = 0.0;
};

// Each phase (slip one way, stick) moves u_n and s along lines in p; the slip halts at p_s,
// then the contact sticks (mu H_tt >= |H_tn|) or slips the other way. The normal velocity's
// slope is a1 before p_s and a2 after; the compression ends where u_n = 0, the restitution where
// the work given back is e^2 of the compression's (the three cases of a halt after, during or
// before the compression's end).
inline PlanarOutcome planar_frictional_impact(const PlanarImpact& c) {
  const double inf = std::numeric_limits<double>::infinity();
  const bool can_stick = c.mu * c.h_tt >= std::abs(c.h_tn);
  const double det = c.h_nn * c.h_tt - c.h_tn * c.h_tn;
  auto slope_n = [&](double sigma) { return c.h_nn - c.mu * sigma * c.h_tn; };
  // the first phase: slip with direction sigma, or stick from rest
  double sigma = 0.0, a1 = 0.0, p_s = inf, a2 = 0.0;
  bool first_sticks = false, then_sticks = can_stick;
  if (c.s_0 != 0.0) {
    sigma = c.s_0 > 0.0 ? 1.0 : -1.0;
    a1 = slope_n(sigma);
    if (c.mu * c.h_tt > sigma * c.h_tn) p_s = std::abs(c.s_0) / (c.mu * c.h_tt - sigma * c.h_tn);
    a2 = can_stick ? det / c.h_tt : slope_n(-sigma);
  } else if (can_stick) {
    first_sticks = true;
    a1 = det / c.h_tt;
  } else {
    sigma = c.h_tn > 0.0 ? 1.0 : -1.0;
    a1 = slope_n(sigma);
  }
  const double v = -c.u_n0;
  const double p_c1 = v / a1;
  double p_f = 0.0;
  if (p_s >= (1.0 + c.e) * p_c1) {  // no halt within the impact
    p_f = (1.0 + c.e) * p_c1;
  } else if (p_s >= p_c1) {  // halt during restitution
    const double v_s = a1 * (p_s - p_c1);
    const double u_f = std::sqrt(v_s * v_s + (a2 / a1) * (c.e * c.e * v * v - v_s * v_s));
    p_f = p_s + (u_f - v_s) / a2;
  } else {  // halt during compression
    const double w_s = v - a1 * p_s;
    const double p_c = p_s + w_s / a2;
    const double u_f = c.e * std::sqrt((a2 / a1) * (v * v - w_s * w_s) + w_s * w_s);
    p_f = p_c + u_f / a2;
  }
  const double stick_ratio = -c.h_tn / c.h_tt;  // dP_t/dp while stuck
  if (first_sticks) return {p_f, stick_ratio * p_f};
  const double before = std::min(p_f, p_s), after = p_f - before;
  double p_t = -c.mu * sigma * before;
  if (after > 0.0) p_t += then_sticks ? stick_ratio * after : c.mu * sigma * after;
  return {p_f, p_t};
}

}  // namespace mimpact::testing
