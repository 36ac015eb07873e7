#pragma once

#include <vector>

namespace mimpact::analysis {

// Nesterenko's long-wave theory of solitary waves in a chain of identical Hertz beads, as
// Coste, Falcon & Fauve (Phys. Rev. E 56, 1997) write it, equation numbers theirs.
struct BeadChain {
  double radius;   // a (m)
  double young;    // E (Pa)
  double poisson;  // nu
  double density;  // rho (kg/m^3)

  double theta() const;  // 3 (1 - nu^2) / (4 E) (m^2/N)
  double mass() const;   // (4/3) pi a^3 rho (kg)
  double C() const;      // sqrt(2 a^3 / (m theta)) (m/s)
};

// Where the force of a wave is measured: between two beads (sphere-sphere Hertz contact),
// or at the force sensor closing the chain, a plane-sphere contact whose deflection is
// 2^(-1/3) of the sphere-sphere one (Coste, Falcon & Fauve 1997, eqs. 18-20).
enum class ForceSite { between_beads, sensor };

// Without static force (eq. 14 with eq. 24's strain): V = C (4/5)^(1/2) (s theta F_m / a^2)^(1/6),
// s = 1 between beads and 2 at the sensor (m/s).
double solitary_wave_speed(const BeadChain& chain, double peak_force, ForceSite site);

// The cos^6 width of the force pulse, F(t) = F_m cos^6(t / tau), tau = sqrt(10) a / V (eq. 28).
double solitary_wave_width(const BeadChain& chain, double speed);

// With a static force F_0 (eqs. 15-22): the sound speed c_s = C (3/2)^(1/2) psi_inf^(1/4), the
// strain ratio psi_m / psi_inf of the wave (eq. 21 at the sensor), y_inf from
// (y_m / y_inf)^(4/5) = psi_m / psi_inf (eq. 17, y_m the other root of W(y) = W(y_inf) of
// eq. 11), and V = c_s (2/3)^(1/2) y_inf^(-1/5) (eq. 22).
struct PrecompressedWave {
  double speed;         // V (m/s)
  double sound_speed;   // c_s (m/s)
  double strain_ratio;  // psi_m / psi_inf
  double y_infinity;    // in (0, (2/3)^(5/2)]
  double y_max;         // y_m, the turning point of the orbit from y_infinity (eq. 11)
};
PrecompressedWave precompressed_solitary_wave(const BeadChain& chain, double peak_force,
                                              double static_force, ForceSite site);

// The force the wave exerts in time, F(t) for t = 0 (the peak) to the pulse's end, at
// `samples` times: eq. 23 at the sensor (eq. 11 integrated from y_m down to y_inf), or its
// sphere-sphere form between beads. Pairs (t in s, F in N).
std::vector<std::pair<double, double>> precompressed_pulse(const BeadChain& chain,
                                                           double peak_force, double static_force,
                                                           ForceSite site, int samples);

}  // namespace mimpact::analysis
