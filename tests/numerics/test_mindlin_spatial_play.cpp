#include "mimpact/numerics/mindlin_spatial_play.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

// A Mindlin spring in space over a step (mindlin_spatial_play.hpp): in a plane it is the planar
// play; slipping along a fixed direction its stretch turns as the closed form tan(phi/2) =
// tan(phi_0/2) exp(-int |s| / r_c); along a turning slip as its equation integrated finely.
namespace mimpact::numerics::mindlin {
namespace {

using Curve = SpatialPlay::Curve;
constexpr double kTurnTolerance = 1e-12;  // rad

StepPolynomial polynomial(std::array<double, 6> c) { return {c}; }

Curve along(const Eigen::Vector3d& direction, const StepPolynomial& size) {
  Curve curve;
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t i = 0; i < 6; ++i) curve[k].c[i] = direction(Eigen::Index(k)) * size.c[i];
  return curve;
}

Curve constant(const Eigen::Vector3d& v) { return along(v, polynomial({1.0})); }

Eigen::Vector3d integral_of(const SpatialPlay& play) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  play.quadrature([&](double, double weight, const Eigen::Vector3d& xi) { sum += weight * xi; });
  return sum;
}

TEST(MindlinSpatialPlay, InAPlaneIsThePlanarPlay) {
  // the planar play's case of two reversals (test_mindlin_play.cpp), in a tilted plane
  const StepPolynomial slip = polynomial({6e-6, -80e-6, 200e-6, -130e-6});
  const StepPolynomial overlap = polynomial({-0.3e-6, 10e-6, -10.5e-6});
  const double c = 0.3;
  const Eigen::Vector3d normal = Eigen::Vector3d(0.3, -0.4, 0.8).normalized();
  const Eigen::Vector3d tangent = normal.cross(Eigen::Vector3d(1.0, 0.0, 0.0)).normalized();
  for (double until : {0.55, 1.0}) {
    const PlanarPlay planar(slip, overlap, c, 0.0, until);
    const SpatialPlay spatial({along(tangent, slip), constant(normal), overlap}, c,
                              Eigen::Vector3d::Zero(), kTurnTolerance, until);
    double planar_integral = 0.0;
    planar.quadrature([&](double, double weight, double xi, const PlaySegment&) {
      planar_integral += weight * xi;
    });
    std::printf("until %.2f: %zu switches (planar %zu), stretch %.15e (planar %.15e)\n", until,
                spatial.switches(), planar.switches(), spatial.final_stretch().dot(tangent),
                planar.final_stretch());
    ASSERT_EQ(spatial.switches(), planar.switches());
    for (std::size_t k = 0; k < planar.switches(); ++k)
      EXPECT_NEAR(spatial.begin()[k].to, planar.begin()[k].to, 1e-13);
    EXPECT_NEAR((spatial.final_stretch() - planar.final_stretch() * tangent).norm(), 0.0,
                1e-12 * c * 1e-6);
    EXPECT_NEAR((integral_of(spatial) - planar_integral * tangent).norm(), 0.0, 1e-12 * c * 1e-6);
  }
}

TEST(MindlinSpatialPlay, TurnsTowardAFixedSlipAsTheClosedForm) {
  // on the cap at phi_0 = 0.8 from the slip, the overlap growing as D (1 + s): tan(phi/2) =
  // tan(phi_0/2) (1 + s)^(-|S| / (c D)), from a gentle turn to a stiff one
  const double c = 0.25, D = 1e-6, phi_0 = 0.8;
  const Eigen::Vector3d normal(0.0, 0.0, 1.0), slip_direction(1.0, 0.0, 0.0);
  for (double ratio : {2.0, 40.0, 4000.0}) {  // |S| / (c D)
    const double size = ratio * c * D;
    const Eigen::Vector3d stretch = c * D * Eigen::Vector3d(std::cos(phi_0), std::sin(phi_0), 0.0);
    const SpatialPlay play({constant(size * slip_direction), constant(normal), polynomial({D, D})},
                           c, stretch, kTurnTolerance);
    ASSERT_EQ(play.switches(), 0u);
    ASSERT_EQ(play.begin()->regime, Regime::slip);
    double worst = 0.0;
    for (double s : {0.1, 0.37, 0.5, 0.81, 1.0}) {
      const double phi = 2.0 * std::atan(std::tan(0.5 * phi_0) * std::pow(1.0 + s, -ratio));
      const Eigen::Vector3d exact =
          c * D * (1.0 + s) * Eigen::Vector3d(std::cos(phi), std::sin(phi), 0.0);
      worst = std::max(worst, (play.stretch_at(*play.begin(), s) - exact).norm() / (c * D));
    }
    std::printf("|S| / (c D) = %g: stretch within %.2e of the cap of the closed form\n", ratio,
                worst);
    EXPECT_LT(worst, 1e-11);
  }
}

// theta' = |S| sin(psi - theta) / (c delta), by RK4 in n steps from `from` to 1: the direction
// of a stretch on the cap
double turned_direction(const Curve& slip, const StepPolynomial& overlap, double c, double theta,
                        int n) {
  auto rate = [&](double s, double angle) {
    const double x = slip[0](s), y = slip[1](s);
    return std::hypot(x, y) * std::sin(std::atan2(y, x) - angle) / (c * overlap(s));
  };
  const double h = 1.0 / n;
  for (int k = 0; k < n; ++k) {
    const double s = k * h;
    const double k1 = rate(s, theta), k2 = rate(s + 0.5 * h, theta + 0.5 * h * k1);
    const double k3 = rate(s + 0.5 * h, theta + 0.5 * h * k2), k4 = rate(s + h, theta + h * k3);
    theta += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  return theta;
}

TEST(MindlinSpatialPlay, FollowsATurningSlipAsItsEquation) {
  // the slip turning by about a radian and growing, the overlap growing: the stretch slips
  // throughout, lagging behind the slip's direction (|s| / r_c up to 3 over the step, some fifty
  // times what a step of a packing sees away from a spring's birth)
  const double c = 0.25;
  const Curve slip = {polynomial({0.8e-6, -0.2e-6, -0.6e-6, 0.1e-6}),
                      polynomial({0.1e-6, 1e-6, -0.2e-6}), polynomial({0.0})};
  const StepPolynomial overlap = polynomial({1e-6, 0.3e-6, 0.2e-6});
  const Eigen::Vector3d stretch = c * 1e-6 * Eigen::Vector3d(std::cos(0.4), std::sin(0.4), 0.0);
  const SpatialPlay play({slip, constant({0.0, 0.0, 1.0}), overlap}, c, stretch, kTurnTolerance);
  ASSERT_EQ(play.switches(), 0u);
  const double theta = turned_direction(slip, overlap, c, 0.4, 100000);
  const Eigen::Vector3d end = play.final_stretch();
  const double error = std::abs(std::remainder(std::atan2(end.y(), end.x()) - theta, 2 * M_PI));
  std::printf("direction at the step's end %.15f, its equation by RK4 %.15f (%.1e apart)\n",
              std::atan2(end.y(), end.x()), theta, error);
  EXPECT_LT(error, 2e-9);
  EXPECT_NEAR(end.norm(), c * overlap(1.0), 1e-15);
}

}  // namespace
}  // namespace mimpact::numerics::mindlin
