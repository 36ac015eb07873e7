#pragma once

#include <algorithm>
#include <array>
#include <cfloat>
#include <cstddef>

#include "mimpact/numerics/root_bracketing.hpp"

// A planar Mindlin spring over one step of an integration that does not stop at its switches
// (the moving geometry's rough groups, docs/design/moving_geometry.md, "Friction within a
// step"). In the plane the spring's stretch is a scalar xi along the contact's tangent, and
// Mindlin's spring under Coulomb's cap (mindlin_spring.hpp) is the play operator of the slip
// with the moving radius r_c = c delta (Krasnosel'skii & Pokrovskii, Systems with Hysteresis,
// 1989): xi' = sigma (stick) while |xi| < c delta, xi = +-c delta (slip) while the slip
// stretches it outward faster than the cap grows, xi = 0 where the contact is open. Given the
// slip and the overlap over the step as polynomials in its share s, the switches are roots of
// polynomials and the stretch is known in closed form between them: a step across a switch is
// amended by what its stages, which saw the stretch's rate jump, could not integrate.
namespace mimpact::numerics::mindlin {

// A polynomial of degree <= 5 in the share s in [0, 1] of a step.
struct StepPolynomial {
  std::array<double, 6> c{};  // coefficients of s^0 ... s^5

  // The quartic through values at s = 0, 1/4, 1/2, 3/4, 1.
  static StepPolynomial through(const std::array<double, 5>& values);
  double operator()(double s) const;
  StepPolynomial derivative() const;
  StepPolynomial antiderivative() const;  // 0 at s = 0 (the quartics' only)
};

// A spring's state between two switches of its step.
enum class Regime : unsigned char { open, stick, slip };

struct PlaySegment {
  double from = 0.0, to = 0.0;  // shares of the step
  Regime regime = Regime::open;
  double sign = 0.0;   // slip: the side of the cap (+-1)
  double start = 0.0;  // stick: the stretch (m) at `from`
};

// The spring's stretch over a step: its segments from s = 0 to the share `until`.
class PlanarPlay {
 public:
  // `slip`: the slip along the tangent times the step (m, the stretch's rate in s while it
  // sticks); `overlap` (m); `cap_ratio` c = mu / (lambda eta) (mindlin::terms); `stretch` (m)
  // the stretch at s = 0, held within the cap there.
  PlanarPlay(const StepPolynomial& slip, const StepPolynomial& overlap, double cap_ratio,
             double stretch, double until = 1.0);

  double stretch_at(const PlaySegment& segment, double s) const;  // m, s within the segment
  double final_stretch() const {
    return stretch_at(segments_[count_ - 1], until_);
  }  // m, at `until`
  const PlaySegment* begin() const { return segments_.data(); }
  const PlaySegment* end() const { return segments_.data() + count_; }
  std::size_t switches() const { return count_ - 1; }

  // Gauss-Legendre nodes on each loaded segment: visit(s, weight, stretch, segment) with the
  // weights summing to the segment's length (exact for polynomials of degree 9).
  template <class Visit>
  void quadrature(Visit&& visit) const;

 private:
  static constexpr std::size_t kMostSegments = 12;  // the rest of the step keeps the last
  void start(double stretch);
  // > 0 within the segment, crossing 0 at its first switch (a segment ends there, or at
  // until_)
  double watched(const PlaySegment& segment, double s) const;
  // the segment that follows one ended at `at` (before until_)
  PlaySegment after(const PlaySegment& ended, double at) const;
  PlaySegment born_at(double at) const;  // the spring born where the contact closes

  StepPolynomial slip_, overlap_, overlap_rate_, slip_integral_;
  double cap_ratio_ = 0.0, until_ = 1.0;
  std::array<PlaySegment, kMostSegments> segments_{};
  std::size_t count_ = 0;
};

namespace play_detail {
// the 5-point Gauss-Legendre nodes on [-1, 1] and their weights
constexpr std::array<double, 5> kNodes = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                          0.5384693101056831, 0.9061798459386640};
constexpr std::array<double, 5> kWeights = {0.2369268850561891, 0.4786286704993665,
                                            0.5688888888888889, 0.4786286704993665,
                                            0.2369268850561891};
// the 5-point rule on [from, to]: visit(s, weight)
template <class Visit>
void gauss_legendre(double from, double to, Visit&& visit) {
  const double middle = 0.5 * (from + to), half = 0.5 * (to - from);
  for (std::size_t k = 0; k < kNodes.size(); ++k)
    visit(middle + half * kNodes[k], half * kWeights[k]);
}

constexpr int kSamples = 8;         // a segment's search for its first switch, per step
constexpr double kLocated = 1e-14;  // of the step: how narrowly a switch is located

// The first share in (a, b] where g falls to 0 or below, g (a continuous function) taken as > 0
// just after a (where a segment begins on its own switch, as a spring born with the cap at 0);
// b + 1 if it does not.
template <class Function>
double first_crossing(Function&& g, double a, double b) {
  double lower = a, g_lower = std::max(g(a), DBL_MIN);
  for (int k = 1; k <= kSamples; ++k) {
    const double upper = k == kSamples ? b : a + (b - a) * k / kSamples;
    const double g_upper = g(upper);
    if (g_upper <= 0.0) return narrow_crossing(g, lower, upper, g_lower, g_upper, kLocated).upper;
    lower = upper;
    g_lower = g_upper;
  }
  return b + 1.0;
}

// Splits a step into its segments, the first begun (segments[0]): each ends where
// watched(segment, s) first falls to 0 (its switch) and the next, after(ended, at), begins
// there, until one reaches `until` or all N are used (the last then keeps the rest of the step).
// Returns their number.
template <class Segment, std::size_t N, class Watched, class After>
std::size_t split_step(std::array<Segment, N>& segments, double until, Watched&& watched,
                       After&& after) {
  for (std::size_t count = 1;; ++count) {
    Segment& segment = segments[count - 1];
    segment.to = first_crossing([&](double s) { return watched(segment, s); }, segment.from, until);
    if (segment.to >= until || count == N) {
      segment.to = until;
      return count;
    }
    segments[count] = after(segment, segment.to);
  }
}
}  // namespace play_detail

template <class Visit>
void PlanarPlay::quadrature(Visit&& visit) const {
  for (const PlaySegment& segment : *this) {
    if (segment.regime == Regime::open || !(segment.to > segment.from)) continue;
    play_detail::gauss_legendre(segment.from, segment.to, [&](double s, double weight) {
      visit(s, weight, stretch_at(segment, s), segment);
    });
  }
}

}  // namespace mimpact::numerics::mindlin
