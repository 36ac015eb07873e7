#pragma once

// One contact's tangential spring under Coulomb's cap: Mindlin's tangential compliance as DEM
// codes integrate it (Mindlin & Deresiewicz 1953; Thornton, Cummins & Cleary 2013; LAMMPS's
// `pair_style granular ... tangential mindlin`, whose continuous limit this is:
// docs/friction.md, section 3). The spring's stretch xi (m, along the contact's 1 or 2 tangent
// rows) carries the tangential force
//   stick:  f_t = -k_t xi,               dxi/dt = s
//   slip:   f_t = -mu F_n d,  d = xi/|xi|,  dxi/dt = s - (d.s) d + r_c' d
// with s the slip, k_t the tangential stiffness and r_c = mu F_n / k_t the radius the stretch is
// capped at (in slip |xi| = r_c: the stretch turns with the slip and follows the cap). A stick
// slips where k_t |xi| reaches mu F_n; a slip sticks where the slip no longer stretches the
// spring faster than the cap moves, d.s < r_c'. A spring is born at the touch, where r_c = 0, and
// slips from there if |s| > r_c'.
namespace mimpact::numerics::mindlin {

// The spring's coefficients at one instant of its contact.
struct Terms {
  double stiffness = 0.0;  // k_t, N/m
  double limit = 0.0;      // mu F_n, N
  double cap_rate = 0.0;   // r_c', m/s
  // a share below the cap where a stretch pushed outward reads as slipping (rates_by_state): an
  // explicit step's stages follow a slipping stretch's cap only to their own order, and read it
  // just under; 0 in the model itself
  double cap_band = 0.0;
  double cap() const { return stiffness > 0.0 ? limit / stiffness : 0.0; }  // r_c, m
};

// For F_n = K delta^eta (an elastic contact) and k_t = lambda dF_n/d delta: k_t =
// lambda eta F_n / delta and r_c = c delta with c = mu / (lambda eta). For Hertz, lambda =
// 4 G*/E* gives Mindlin's k_t = 8 G* a.
Terms terms(double ratio, double exponent, double mu, double normal_force, double delta,
            double delta_rate);

struct Spring {
  enum class Mode : unsigned char { touch, stick, slip };
  Mode mode = Mode::touch;  // touch: just born, its mode chosen where its first segment starts

  // A spring just born (mode touch) at overlap delta: slip with xi = r_c s/|s| where |s| > r_c',
  // else stick with the stretch since the touch, xi = s delta/delta' (= s r_c/r_c').
  void start(double* xi, const double* slip, int rows, const Terms& terms);
  // f_t (N) and dxi/dt (m/s) along the rows.
  void rates(const double* xi, const double* slip, int rows, const Terms& terms, double* force,
             double* xi_rate) const;
  // > 0 before its switch, crossing 0 where it happens: mu F_n - k_t |xi| in stick (with a margin
  // of a few ulp of mu F_n, so that a stick begun on the cap is not ended by the round-off of its
  // start), d.s - r_c' in slip.
  double watched(const double* xi, const double* slip, int rows, const Terms& terms) const;
  // Past its switch: a stick slips; a slip sticks, its stretch put on the cap, xi = r_c d.
  void pass(double* xi, int rows, const Terms& terms);
};

// The same spring with its mode read from its state, for an integration that locates no switch
// (the moving geometry's groups, whose error control shortens the steps across one): it slips
// where its stretch has reached the cap and the slip stretches it further, d.s > r_c', else
// sticks; its force is capped at mu F_n either way, so that it is continuous in the stretch.
// Writes f_t and dxi/dt along the `rows` (1 to 3) components, and says which it read: under
// the cap, on it (the force capped, the stretch not pushed further out) or slipping (within
// terms.cap_band of the cap).
enum class ByState : unsigned char { under_cap, on_cap, slipping };
ByState rates_by_state(const double* xi, const double* slip, int rows, const Terms& terms,
                       double* force, double* xi_rate);
// The same along one row (a planar contact's tangent), without the norms: the same numbers.
ByState rates_by_state(double xi, double slip, const Terms& terms, double& force, double& xi_rate);

}  // namespace mimpact::numerics::mindlin
