#pragma once

#include <cmath>
#include <span>
#include <vector>

namespace mimpact::analysis {

// What Nguyen & Brogliato (2011, section 5, eqs. 40-43) measure of a force pulse F(t) at a
// contact.
struct PulseMeasures {
  double peak = 0.0;          // F_m (N)
  double time_of_peak = 0.0;  // T, the time of flight (s, on the record's clock)
  // tau of F_m cos^6((t - T) / tau) fitted to the front (s): the pulse rises from 0 to
  // F_m over pi tau / 2 and its full width at half height is 0.942 tau
  double width = 0.0;
  double front_impulse = 0.0;  // P_F, the integral of F up to T + tau (N s)
  double tail_impulse = 0.0;   // P_T, the integral of F after T + tau (N s)
};

// Measures the pulse of largest force within [begin, end] of a sampled force (times
// increasing). tau is the least-squares fit of F_m cos^6((t - T) / tau), F_m and T held at
// the peak, to the samples of the front: from the last zero force before the peak up to it
// (the method of Nguyen & Brogliato (2011) and of its reference [18]). Integrals are trapezoidal.
// Throws InvalidInput for records of different lengths, decreasing times or no positive force.
PulseMeasures measure_pulse(std::span<const double> time, std::span<const double> force,
                            double begin = -INFINITY, double end = INFINITY);

// The wave speed through bead i between its left and right contacts (Nguyen & Brogliato 2011,
// eq. 41): phi_i / (T_i - T_(i-1)), phi_i the bead's diameter (m/s).
double wave_speed(double diameter, double time_left, double time_right);

// Distinct pulses of a force record, as seen at a wall after a stepped chain (Nguyen &
// Brogliato 2011, section 6): local maxima of at least `threshold` (N), two kept maxima being
// separated by a fall below half the smaller one; otherwise the larger stands for both. In time
// order.
struct Peak {
  double time;
  double force;
};
std::vector<Peak> find_pulses(std::span<const double> time, std::span<const double> force,
                              double threshold);

}  // namespace mimpact::analysis
