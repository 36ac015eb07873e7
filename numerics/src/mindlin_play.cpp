#include "mimpact/numerics/mindlin_play.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace mimpact::numerics::mindlin {

namespace {

// the inverse of the Vandermonde matrix of s = 0, 1/4, 1/2, 3/4, 1 (rows: coefficients)
constexpr double kInverse[5][5] = {{1.0, 0.0, 0.0, 0.0, 0.0},
                                   {-25.0 / 3.0, 16.0, -12.0, 16.0 / 3.0, -1.0},
                                   {70.0 / 3.0, -208.0 / 3.0, 76.0, -112.0 / 3.0, 22.0 / 3.0},
                                   {-80.0 / 3.0, 96.0, -128.0, 224.0 / 3.0, -16.0},
                                   {32.0 / 3.0, -128.0 / 3.0, 64.0, -128.0 / 3.0, 32.0 / 3.0}};

constexpr double kOnTheCap = 1e-9;  // relative: a stretch this near the cap starts on it

}  // namespace

StepPolynomial StepPolynomial::through(const std::array<double, 5>& values) {
  StepPolynomial p;
  for (std::size_t i = 0; i < 5; ++i)
    for (std::size_t k = 0; k < 5; ++k) p.c[i] += kInverse[i][k] * values[k];
  return p;
}

double StepPolynomial::operator()(double s) const {
  double sum = c[5];
  for (std::size_t i = 5; i-- > 0;) sum = sum * s + c[i];
  return sum;
}

StepPolynomial StepPolynomial::derivative() const {
  StepPolynomial p;
  for (std::size_t i = 1; i < c.size(); ++i) p.c[i - 1] = double(i) * c[i];
  return p;
}

StepPolynomial StepPolynomial::antiderivative() const {
  StepPolynomial p;
  for (std::size_t i = 0; i + 1 < c.size(); ++i) p.c[i + 1] = c[i] / double(i + 1);
  return p;
}

PlanarPlay::PlanarPlay(const StepPolynomial& slip, const StepPolynomial& overlap, double cap_ratio,
                       double stretch, double until)
    : slip_(slip),
      overlap_(overlap),
      overlap_rate_(overlap.derivative()),
      slip_integral_(slip.antiderivative()),
      cap_ratio_(cap_ratio),
      until_(until) {
  start(stretch);
  count_ = play_detail::split_step(
      segments_, until_,
      [this](const PlaySegment& segment, double s) { return watched(segment, s); },
      [this](const PlaySegment& ended, double at) { return after(ended, at); });
}

double PlanarPlay::stretch_at(const PlaySegment& segment, double s) const {
  switch (segment.regime) {
    case Regime::open:
      return 0.0;
    case Regime::stick:
      return segment.start + (slip_integral_(s) - slip_integral_(segment.from));
    case Regime::slip:
      return segment.sign * cap_ratio_ * overlap_(s);
  }
  return 0.0;
}

void PlanarPlay::start(double stretch) {
  const double overlap = overlap_(0.0);
  if (!(overlap > 0.0)) {
    segments_[0] = {.regime = Regime::open};
    return;
  }
  const double cap = cap_ratio_ * overlap;
  const double sign = stretch < 0.0 ? -1.0 : 1.0;
  const bool on_cap = std::abs(stretch) >= cap * (1.0 - kOnTheCap);
  if (on_cap && sign * slip_(0.0) > cap_ratio_ * overlap_rate_(0.0)) {
    segments_[0] = {.regime = Regime::slip, .sign = sign};
    return;
  }
  segments_[0] = {.regime = Regime::stick, .start = std::clamp(stretch, -cap, cap)};
}

double PlanarPlay::watched(const PlaySegment& segment, double s) const {
  switch (segment.regime) {
    case Regime::open:  // until the contact closes
      return -overlap_(s);
    case Regime::stick: {  // until the stretch reaches the cap, or the contact opens
      const double cap = cap_ratio_ * overlap_(s), xi = stretch_at(segment, s);
      return std::min({cap - xi, cap + xi, overlap_(s)});
    }
    case Regime::slip:  // until the slip no longer outruns the cap, or the contact opens
      return std::min(segment.sign * slip_(s) - cap_ratio_ * overlap_rate_(s), overlap_(s));
  }
  return overlap_(s);
}

PlaySegment PlanarPlay::born_at(double at) const {
  const double slip = slip_(at);
  if (std::abs(slip) > cap_ratio_ * overlap_rate_(at))
    return {.from = at, .regime = Regime::slip, .sign = slip < 0.0 ? -1.0 : 1.0};
  return {.from = at, .regime = Regime::stick};
}

PlaySegment PlanarPlay::after(const PlaySegment& ended, double at) const {
  if (ended.regime == Regime::open) return born_at(at);
  if (!(overlap_(at) > 0.0)) return {.from = at, .regime = Regime::open};
  if (ended.regime == Regime::slip)
    return {.from = at, .regime = Regime::stick, .start = stretch_at(ended, at)};
  const double stretch = stretch_at(ended, at);
  return {.from = at, .regime = Regime::slip, .sign = stretch < 0.0 ? -1.0 : 1.0};
}

}  // namespace mimpact::numerics::mindlin
