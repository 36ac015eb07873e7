#include "mimpact/numerics/mindlin_play.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

// A planar Mindlin spring over a step, its switches located on polynomials
// (mindlin_play.hpp): against closed forms and against the catch-up scheme of the play operator
// (the stretch moved by the slip and clamped to the cap, step after step, as DEM codes do),
// which converges to it at first order.
namespace mimpact::numerics::mindlin {
namespace {

StepPolynomial polynomial(std::array<double, 6> c) { return {c}; }

// The catch-up scheme over [0, until] in n steps: the stretch at the end and its integral.
struct CatchUp {
  double stretch = 0.0, integral = 0.0;
};
CatchUp catch_up(const StepPolynomial& slip, const StepPolynomial& overlap, double c, double xi,
                 double until, int n) {
  const StepPolynomial moved = slip.antiderivative();
  CatchUp out{.stretch = xi};
  for (int k = 0; k < n; ++k) {
    const double s0 = until * k / n, s1 = until * (k + 1) / n;
    const double cap = c * std::max(overlap(s1), 0.0);
    const double before = out.stretch;
    out.stretch = overlap(s1) > 0.0 ? std::clamp(before + moved(s1) - moved(s0), -cap, cap) : 0.0;
    out.integral += 0.5 * (before + out.stretch) * (s1 - s0);
  }
  return out;
}

double integral_of(const PlanarPlay& play) {
  double sum = 0.0;
  play.quadrature(
      [&](double, double weight, double xi, const PlaySegment&) { sum += weight * xi; });
  return sum;
}

TEST(MindlinPlay, QuarticThroughItsNodes) {
  const StepPolynomial p = StepPolynomial::through({1.0, -2.0, 0.5, 3.0, 7.0});
  const std::array<double, 5> expected = {1.0, -2.0, 0.5, 3.0, 7.0};
  for (int k = 0; k < 5; ++k) EXPECT_NEAR(p(0.25 * k), expected[std::size_t(k)], 1e-13);
  const StepPolynomial q = polynomial({0.3, -1.0, 2.0, 0.7, -0.4, 0.0});
  const StepPolynomial fit = StepPolynomial::through({q(0.0), q(0.25), q(0.5), q(0.75), q(1.0)});
  for (std::size_t i = 0; i < 5; ++i) EXPECT_NEAR(fit.c[i], q.c[i], 1e-13);
}

TEST(MindlinPlay, SticksThenSlipsAtTheClosedFormsShare) {
  // constant overlap D and slip: the stretch grows as sigma s until it reaches c D
  const double c = 0.25, D = 2e-6, sigma = 1e-6;
  const PlanarPlay play(polynomial({sigma}), polynomial({D}), c, 0.0);
  ASSERT_EQ(play.switches(), 1u);
  const double share = c * D / sigma;
  std::printf("stick to slip at %.15f (closed form %.15f)\n", play.begin()->to, share);
  EXPECT_NEAR(play.begin()->to, share, 1e-13);
  EXPECT_EQ(play.begin()[1].regime, Regime::slip);
  EXPECT_DOUBLE_EQ(play.final_stretch(), c * D);
  const double exact = 0.5 * sigma * share * share + c * D * (1.0 - share);
  EXPECT_NEAR(integral_of(play), exact, 1e-14 * exact);
}

TEST(MindlinPlay, IsBornWhereTheContactClosesInTheRegimeItsRatesChoose) {
  // the overlap a (s - 0.3) from its touch: the cap grows at c a, the slip at sigma
  const double c = 0.25, a = 4e-6;
  for (double sigma : {0.5e-6, 2e-6}) {
    const PlanarPlay play(polynomial({sigma}), polynomial({-0.3 * a, a}), c, 0.0);
    ASSERT_EQ(play.switches(), 1u);
    EXPECT_NEAR(play.begin()->to, 0.3, 1e-13);
    const bool slips = sigma > c * a;
    EXPECT_EQ(play.begin()[1].regime, slips ? Regime::slip : Regime::stick);
    EXPECT_NEAR(play.final_stretch(), (slips ? c * a : sigma) * 0.7, 1e-13 * sigma);
  }
}

TEST(MindlinPlay, ReversesAndMeetsTheCatchUpScheme) {
  // the contact closing, its overlap growing then falling to its opening, the slip reversing
  // twice: born slipping at 0.031, stick at 0.046, slip at 0.345 (on the cap's other side),
  // stick at 0.525, slip at 0.836, open at 0.921
  const StepPolynomial slip = polynomial({6e-6, -80e-6, 200e-6, -130e-6});
  const StepPolynomial overlap = polynomial({-0.3e-6, 10e-6, -10.5e-6});
  const double c = 0.3;
  for (double until : {0.55, 1.0}) {
    const PlanarPlay play(slip, overlap, c, 0.0, until);
    const CatchUp reference = catch_up(slip, overlap, c, 0.0, until, 2000000);
    std::printf("until %.2f: %zu switches, stretch %.6e (catch-up %.6e), integral %.6e (%.6e)\n",
                until, play.switches(), play.final_stretch(), reference.stretch, integral_of(play),
                reference.integral);
    EXPECT_EQ(play.switches(), until < 1.0 ? 4u : 6u);
    EXPECT_NEAR(play.final_stretch(), reference.stretch, 1e-5 * c * 1e-6);
    EXPECT_NEAR(integral_of(play), reference.integral, 1e-5 * c * 1e-6);
  }
}

}  // namespace
}  // namespace mimpact::numerics::mindlin
