// The adaptive LZB impact with Coulomb friction (docs/model.md, "Friction") against the closed
// forms of a planar single-contact impact: a sphere on a rigid flat (gross slip, rolling, with
// and without spin) and Stronge's slender bar, whose slip halts and sticks or reverses.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "../support/planar_discs.hpp"
#include "../support/planar_frictional_impact.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/numerics/lzb_adaptive_integrator.hpp"
#include "mimpact/numerics/lzb_asynchronous_integrator.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace mimpact::numerics {
namespace {

using Eigen::Index;
using Eigen::Vector3d;
using testing::Discs;
using testing::energy_of;
constexpr double kTightest = 1e-13;  // LzbAdaptiveOptions' smallest tolerance

Eigen::SparseMatrix<double> one_by_one(double value) {
  Eigen::SparseMatrix<double> matrix(1, 1);
  matrix.insert(0, 0) = value;
  matrix.makeCompressed();
  return matrix;
}

// One planar body (x, y, angle) at one contact of normal row w_n and tangent row w_t.
struct PlanarContact {
  Vector3d w_n, w_t, inverse_mass, velocity;
  double mu, e;

  double h_nn() const { return w_n.dot(inverse_mass.cwiseProduct(w_n)); }
  double h_tn() const { return w_t.dot(inverse_mass.cwiseProduct(w_n)); }
  double h_tt() const { return w_t.dot(inverse_mass.cwiseProduct(w_t)); }
  testing::PlanarImpact closed_form_input() const {
    return {h_nn(), h_tn(), h_tt(), w_n.dot(velocity), w_t.dot(velocity), mu, e};
  }
  double kinetic_energy(const Vector3d& v) const {
    return 0.5 * v.dot(inverse_mass.cwiseInverse().cwiseProduct(v));
  }
};

struct PlanarRun {
  ImpactResult result;
  Vector3d velocity;  // the body's after the impact
};

PlanarRun integrate(const PlanarContact& c, ImpactIntegrator& integrator) {
  TangentialRows rows{.normal_to_tangent = one_by_one(c.h_tn()),
                      .tangent = one_by_one(c.h_tt()),
                      .slip_minus = Eigen::VectorXd::Constant(1, c.w_t.dot(c.velocity)),
                      .first_row = {0, 1}};
  const ContactLaw laws[] = {
      {.stiffness = 1e9, .exponent = 1.5, .restitution = c.e, .friction = c.mu}};
  PlanarRun run{
      integrator.integrate(one_by_one(c.h_nn()),
                           Eigen::VectorXd::Constant(1, c.w_n.dot(c.velocity)), laws, rows),
      c.velocity};
  run.velocity += c.inverse_mass.cwiseProduct(c.w_n * run.result.impulse(0) +
                                              c.w_t * run.result.tangential_impulse(0));
  return run;
}

// The kinetic energy lost is the normal work plus the slip work, to the round-off of summing
// them over the steps, and slip only takes energy.
void expect_energy_booked(const PlanarContact& c, const PlanarRun& run, const std::string& what) {
  const double before = c.kinetic_energy(c.velocity);
  const double lost = before - c.kinetic_energy(run.velocity);
  const double round_off = 1e-12 + DBL_EPSILON * double(run.result.steps);
  EXPECT_NEAR(lost, run.result.work.sum() + run.result.slip_work.sum(), round_off * before) << what;
  EXPECT_GE(run.result.slip_work(0), -1e-13 * before) << what;
}

// A solid sphere (I = 2/5 m r^2) strikes a rigid flat at incidence theta from the normal with
// speed V and spin omega: P_n = (1 + e) m V cos(theta). If the slip s- = V sin(theta) + r omega
// outlasts the impact (|s-| >= mu (1 + e) V cos(theta) (1 + m r^2 / I)) the centre's tangential
// velocity drops by mu (1 + e) V cos(theta) and the slip by that times 1 + m r^2 / I = 7/2;
// otherwise the sphere leaves rolling, s+ = 0, its centre at v_t - 2/7 s- (5/7 v_t without
// spin). To 1e-10 of V at the tightest tolerance.
TEST(FrictionalImpact, SphereOnFlatGrossSlipAndRolling) {
  const double m = 0.1, r = 0.01, inertia = 0.4 * m * r * r, speed = 1.0;
  LzbAdaptiveIntegrator integrator({.tolerance = kTightest});
  double worst = 0.0;
  int rolling = 0, slipping = 0;
  for (double degrees : {0.0, 10.0, 30.0, 45.0, 60.0, 80.0, 89.0})
    for (double spin : {0.0, 30.0, -80.0})
      for (double mu : {0.0, 0.05, 0.2, 0.5, 1.0})
        for (double e : {1.0, 0.6}) {
          const double theta = degrees * std::numbers::pi / 180.0;
          const PlanarContact c{
              .w_n = {0.0, 1.0, 0.0},
              .w_t = {1.0, 0.0, r},
              .inverse_mass = {1.0 / m, 1.0 / m, 1.0 / inertia},
              .velocity = {speed * std::sin(theta), -speed * std::cos(theta), spin},
              .mu = mu,
              .e = e};
          const PlanarRun run = integrate(c, integrator);
          const std::string what = std::to_string(degrees) + " deg, spin " + std::to_string(spin) +
                                   ", mu " + std::to_string(mu) + ", e " + std::to_string(e);
          ASSERT_EQ(run.result.status, ImpactStatus::terminated) << what;
          const double normal = speed * std::cos(theta), slip = c.w_t.dot(c.velocity);
          const double drop = mu * (1.0 + e) * normal;
          const double ratio = 1.0 + m * r * r / inertia;
          const bool gross = std::abs(slip) >= drop * ratio;
          const double sign = slip > 0.0 ? 1.0 : -1.0;
          const double v_t = gross ? c.velocity(0) - sign * drop : c.velocity(0) - slip / ratio;
          const double s_plus = gross ? slip - sign * drop * ratio : 0.0;
          (gross ? slipping : rolling) += 1;
          const double errors[] = {run.velocity(1) - e * normal, run.velocity(0) - v_t,
                                   run.result.slip(0) - s_plus,
                                   run.result.slip(0) - c.w_t.dot(run.velocity)};
          for (double error : errors) {
            worst = std::max(worst, std::abs(error) / speed);
            EXPECT_NEAR(error, 0.0, 1e-10 * speed) << what;
          }
          expect_energy_booked(c, run, what);
        }
  std::printf("sphere on a flat: %d rolling, %d in gross slip, worst error %.2e of V\n", rolling,
              slipping, worst);
  EXPECT_GT(rolling, 40);
  EXPECT_GT(slipping, 40);
}

// Stronge's slender bar (mass m, length L, I = m L^2 / 12) at angle theta to a rough floor, its
// lower end striking with centre velocity (u, -V): m H_tt = 1 + 3 sin^2, m H_tn = -3 sin cos,
// m H_nn = 1 + 3 cos^2. The contact sticks where mu >= 3 tan / (1 + 4 tan^2); with u > 0 the
// slip halts and then sticks or reverses (the energetic restitution after the halt differs from
// Newton's and Poisson's).
PlanarContact bar(double theta_degrees, double mu, double e, double u, double spin) {
  const double m = 1.0, length = 1.0, theta = theta_degrees * std::numbers::pi / 180.0;
  const double half = 0.5 * length;
  return {.w_n = {0.0, 1.0, -half * std::cos(theta)},
          .w_t = {1.0, 0.0, half * std::sin(theta)},
          .inverse_mass = {1.0 / m, 1.0 / m, 12.0 / (m * length * length)},
          .velocity = {u, -1.0, spin},
          .mu = mu,
          .e = e};
}

// The closed form's worked cases (m = 1 kg, L = 1 m, V = 1 m/s, no spin): the normal and
// tangential impulses and the bar's velocities after the impact, to the 6 decimals given.
TEST(FrictionalImpact, StrongeBarWorkedCases) {
  struct Case {
    double theta, mu, e, u, p_n, p_t, vx, vy, omega, s;
  };
  const Case cases[] = {
      {30, 0.2, 0.5, 0.0, 0.501640, 0.100328, 0.100328, -0.498360, -2.305614, -0.476075},
      {30, 0.9, 0.5, 0.0, 0.65625, 0.487139, 0.487139, -0.34375, -1.948557, 0.0},
      {30, 0.2, 0.5, 0.5, 0.436298, -0.034023, 0.465977, -0.563702, -2.369142, -0.126309},
      {30, 0.2, 0.5, 0.1, 0.486326, 0.073009, 0.173009, -0.513674, -2.307997, -0.403991},
      {30, 0.9, 0.5, 0.5, 0.436319, 0.038169, 0.538169, -0.563681, -2.152675, 0.0},
      {30, 0.9, 0.5, -0.5, 0.720854, 0.648768, 0.148768, -0.279146, -1.799361, -0.301072},
      {30, 0.5, 0.5, -0.5, 0.576816, 0.288408, -0.211592, -0.423184, -2.132001, -0.744592},
      {30, 0.6, 0.5, 0.05, 0.587183, 0.326767, 0.376767, -0.412817, -2.070789, -0.140930},
      {60, 0.3, 0.8, 1.0, 0.952557, 0.021919, 1.021919, -0.047443, -2.743775, -0.166170},
      {50, 0.5, 1.0, 0.8, 0.870084, 0.155072, 0.955072, -0.129916, -2.642923, -0.057227},
  };
  LzbAdaptiveIntegrator integrator({.tolerance = kTightest});
  for (const Case& k : cases) {
    const PlanarContact c = bar(k.theta, k.mu, k.e, k.u, 0.0);
    const PlanarRun run = integrate(c, integrator);
    const std::string what =
        std::to_string(k.theta) + " deg, mu " + std::to_string(k.mu) + ", u " + std::to_string(k.u);
    const double got[] = {run.result.impulse(0), run.result.tangential_impulse(0),
                          run.velocity(0),       run.velocity(1),
                          run.velocity(2),       run.result.slip(0)};
    const double expected[] = {k.p_n, k.p_t, k.vx, k.vy, k.omega, k.s};
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(got[i], expected[i], 1e-6) << what << ", entry " << i;
    expect_energy_booked(c, run, what);
  }
}

// Over the bar's angles, frictions, restitutions, sliding speeds and spins (every regime:
// gross slip, stick from rest, a halt in compression or restitution, then stick or reversal)
// the integration and the closed form agree to 1e-10 of V.
TEST(FrictionalImpact, StrongeBarAgreesWithTheClosedForm) {
  LzbAdaptiveIntegrator integrator({.tolerance = kTightest});
  double worst = 0.0;
  for (double theta : {10.0, 26.5, 45.0, 70.0})
    for (double mu : {0.1, 0.4, 0.75, 1.2})
      for (double e : {1.0, 0.5})
        for (double u : {-0.6, 0.0, 0.08, 0.4, 1.5})
          for (double spin : {0.0, 1.5}) {
            const PlanarContact c = bar(theta, mu, e, u, spin);
            if (c.w_n.dot(c.velocity) >= 0.0) continue;  // the spin lifts the end: no impact
            const testing::PlanarOutcome exact =
                testing::planar_frictional_impact(c.closed_form_input());
            const PlanarRun run = integrate(c, integrator);
            const std::string what = std::to_string(theta) + " deg, mu " + std::to_string(mu) +
                                     ", e " + std::to_string(e) + ", u " + std::to_string(u) +
                                     ", spin " + std::to_string(spin);
            // impulses in units of m V (1 kg m/s): velocities to the same figure
            const double errors[] = {run.result.impulse(0) - exact.p_n,
                                     run.result.tangential_impulse(0) - exact.p_t};
            for (double error : errors) {
              worst = std::max(worst, std::abs(error));
              EXPECT_NEAR(error, 0.0, 1e-10) << what;
            }
            expect_energy_booked(c, run, what);
          }
  std::printf("slender bar: worst impulse error %.2e of m V\n", worst);
}

// Keller's impact in space (J. Appl. Mech. 53, 1986), where the slip's direction turns: one
// contact with H_tn = 0, H_tt = diag(k1, k2) (a solid ellipsoid of semi-axes 2, 1, 1 standing on
// its short axis: k1 = 2, k2 = 3.5 per kg), H_nn = 1. The normal impulse is (1 + e) |u_n0|; the
// slip s = s0 + H_tt P_t follows the hodograph y / y0 = (x / x0)^(k2 / k1) whatever mu, until it
// stops, and then sticks (H_tn = 0): P_t = -H_tt^-1 s0. With mu = 0.3 the slip outlasts the
// impact (it would stop at p = 1.960868 > 1.5), with mu = 0.5 it stops at 1.176521.
TEST(FrictionalImpact, KellerSlipTurnsAlongItsHodograph) {
  const double k1 = 2.0, k2 = 3.5, e = 0.5;
  Eigen::SparseMatrix<double> tangent(2, 2);
  tangent.insert(0, 0) = k1;
  tangent.insert(1, 1) = k2;
  TangentialRows rows{.normal_to_tangent = Eigen::SparseMatrix<double>(2, 1),
                      .tangent = tangent,
                      .slip_minus = Eigen::Vector2d(1.0, 1.0),
                      .first_row = {0, 2}};
  LzbAdaptiveIntegrator integrator({.tolerance = kTightest});
  for (double mu : {0.3, 0.5}) {
    const ContactLaw laws[] = {
        {.stiffness = 1e9, .exponent = 1.5, .restitution = e, .friction = mu}};
    const ImpactResult result =
        integrator.integrate(one_by_one(1.0), Eigen::VectorXd::Constant(1, -1.0), laws, rows);
    const double x = result.slip(0), y = result.slip(1);
    std::printf("mu %.1f: P_n %.15f, P_t (%.6f, %.6f), s+ (%.6f, %.6f)\n", mu, result.impulse(0),
                result.tangential_impulse(0), result.tangential_impulse(1), x, y);
    EXPECT_NEAR(result.impulse(0), 1.0 + e, 1e-10);
    EXPECT_NEAR(result.velocity(0), e, 1e-10);
    EXPECT_NEAR(x, 1.0 + k1 * result.tangential_impulse(0), 1e-12);
    if (mu == 0.3) {  // still slipping: on the hodograph, |P_t| = mu P_n traced along a turn
      EXPECT_NEAR(y, std::pow(x, k2 / k1), 1e-10);
      EXPECT_NEAR(x, 0.269160, 1e-6);
      EXPECT_NEAR(y, 0.100581, 1e-6);
      EXPECT_NEAR(result.tangential_impulse(0), -0.365420, 1e-6);
      EXPECT_NEAR(result.tangential_impulse(1), -0.256977, 1e-6);
      EXPECT_LT(result.tangential_impulse.norm(), mu * result.impulse(0));
    } else {  // stopped, then stuck
      EXPECT_NEAR(result.tangential_impulse(0), -1.0 / k1, 1e-10);
      EXPECT_NEAR(result.tangential_impulse(1), -1.0 / k2, 1e-10);
      EXPECT_NEAR(std::hypot(x, y), 0.0, 1e-10);
    }
    EXPECT_GT(result.slip_work.sum(), 0.0);
  }
}

// The impulse steps with friction: exact for the sphere on a flat (a lone contact at any
// delta_p, its slip not moving its normal velocity), and first order in delta_p for the bar,
// whose slip does (H_tn != 0), against the closed form.
TEST(FrictionalImpact, ImpulseStepsSphereExactAndBarFirstOrder) {
  const double m = 0.1, r = 0.01, inertia = 0.4 * m * r * r;
  LzbImpulseIntegrator coarse({.relative_delta_p = 1e-3});
  double worst_sphere = 0.0;
  for (double degrees : {0.0, 30.0, 80.0})
    for (double mu : {0.05, 0.5}) {
      const double theta = degrees * std::numbers::pi / 180.0;
      const PlanarContact c{.w_n = {0.0, 1.0, 0.0},
                            .w_t = {1.0, 0.0, r},
                            .inverse_mass = {1.0 / m, 1.0 / m, 1.0 / inertia},
                            .velocity = {std::sin(theta), -std::cos(theta), 30.0},
                            .mu = mu,
                            .e = 0.6};
      const testing::PlanarOutcome exact = testing::planar_frictional_impact(c.closed_form_input());
      const PlanarRun run = integrate(c, coarse);
      for (double error :
           {run.result.impulse(0) - exact.p_n, run.result.tangential_impulse(0) - exact.p_t})
        worst_sphere = std::max(worst_sphere, std::abs(error) / m);
      expect_energy_booked(c, run, std::to_string(degrees) + " deg, mu " + std::to_string(mu));
    }
  std::printf("sphere on a flat, impulse steps of 1e-3 m V: worst error %.2e of V\n", worst_sphere);
  EXPECT_LT(worst_sphere, 1e-12);

  // the bar's halt in compression then reversal, and in restitution then stick
  for (const PlanarContact& c : {bar(30.0, 0.2, 0.5, 0.1, 0.0), bar(30.0, 0.9, 0.5, 0.5, 0.0)}) {
    const testing::PlanarOutcome exact = testing::planar_frictional_impact(c.closed_form_input());
    double coarsest = 0.0, error = 0.0;
    for (double relative : {1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
      LzbImpulseIntegrator steps({.relative_delta_p = relative});
      const PlanarRun run = integrate(c, steps);
      error = std::hypot(run.result.impulse(0) - exact.p_n,
                         run.result.tangential_impulse(0) - exact.p_t);
      std::printf("bar, impulse steps of %.0e m V: error %.2e m V\n", relative, error);
      EXPECT_LT(error, 0.1 * relative);
      if (coarsest == 0.0) coarsest = error;
      expect_energy_booked(c, run, "bar at " + std::to_string(relative));
    }
    EXPECT_LT(error, 1e-3 * coarsest);  // four decades of delta_p: at least first order
  }
}

struct DiscsRun {
  ImpactResult result;
  Eigen::VectorXd velocity;
};

DiscsRun integrate(const Discs& d, double mu, double e, ImpactIntegrator& integrator) {
  Eigen::MatrixXd w_n, w_t;
  d.columns(w_n, w_t);
  const Eigen::VectorXd inverse = d.inverse_mass();
  const Eigen::MatrixXd h = w_n.transpose() * inverse.asDiagonal() * w_n;
  const Index m = h.rows();
  TangentialRows rows{
      .normal_to_tangent = (w_t.transpose() * inverse.asDiagonal() * w_n).sparseView(0.0, 0.0),
      .tangent = (w_t.transpose() * inverse.asDiagonal() * w_t).sparseView(0.0, 0.0),
      .slip_minus = w_t.transpose() * d.velocity,
      .first_row = {}};
  for (Index j = 0; j <= m; ++j) rows.first_row.push_back(j);
  const std::vector<ContactLaw> laws(
      std::size_t(m), {.stiffness = 1e9, .exponent = 1.5, .restitution = e, .friction = mu});
  DiscsRun run{
      integrator.integrate(h.sparseView(0.0, 0.0), w_n.transpose() * d.velocity, laws, rows),
      d.velocity};
  run.velocity +=
      inverse.asDiagonal() * (w_n * run.result.impulse + w_t * run.result.tangential_impulse);
  return run;
}

// A spinning striker hits two touching discs off-centre (a break of three billiard balls): many
// contacts, slip and stick, coupled through the bodies. The momentum and the angular momentum
// about the origin are kept to 1e-12, the energy lost is the normal and slip work, and the
// adaptive integration and the impulse steps (two independent methods) agree to their error.
TEST(FrictionalImpact, ThreeDiscBreakKeepsMomentaAndAgreesAcrossIntegrators) {
  const double r = 0.0286, m = 0.17;  // billiard balls
  Discs d{.mass = {m, m, m}, .radius = {r, r, r}, .position = {}, .velocity = {}, .pairs = {}};
  // the targets touch side by side; the striker comes up at disc 1, 30 degrees off its centre
  const double c = std::cos(std::numbers::pi / 6.0);
  d.position.resize(9);
  d.position << -2.0 * r, -2.0 * r * c, 0.0, -r, 0.0, 0.0, r, 0.0, 0.0;
  d.velocity = Eigen::VectorXd::Zero(9);
  d.velocity << 0.0, 2.0, 40.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0;
  d.pairs = {{0, 1}, {1, 2}};
  auto momenta = [&](const Eigen::VectorXd& v) {
    Eigen::Vector3d total = Eigen::Vector3d::Zero();  // p_x, p_y, L_z about the origin
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector2d x = d.centre(i), p = m * v.segment<2>(3 * i);
      total += Eigen::Vector3d(p.x(), p.y(),
                               x.x() * p.y() - x.y() * p.x() + 0.4 * m * r * r * v(3 * i + 2));
    }
    return total;
  };
  // the largest difference of two runs' velocities, the spins as their contact points' speed
  auto difference = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
    double largest = 0.0;
    for (int i = 0; i < 9; ++i)
      largest = std::max(largest, std::abs(x(i) - y(i)) * (i % 3 == 2 ? r : 1.0));
    return largest;
  };
  const double speed = 2.0, kinetic = energy_of(d, d.velocity);
  for (double mu : {0.1, 0.6}) {
    LzbAdaptiveIntegrator adaptive({.tolerance = 1e-10});
    const DiscsRun a = integrate(d, mu, 0.9, adaptive);
    EXPECT_LT((momenta(a.velocity) - momenta(d.velocity)).cwiseAbs().maxCoeff(), 1e-12 * m * speed);
    EXPECT_NEAR(kinetic - energy_of(d, a.velocity), a.result.work.sum() + a.result.slip_work.sum(),
                1e-12 * kinetic);
    EXPECT_GT(a.result.slip_work.minCoeff(), -1e-12 * kinetic);
    EXPECT_GT(a.result.slip_work.sum(), 0.1 * kinetic);
    double coarse = 0.0;
    for (double relative : {1e-4, 1e-5}) {
      LzbImpulseIntegrator steps({.relative_delta_p = relative});
      const double gap = difference(a.velocity, integrate(d, mu, 0.9, steps).velocity) / speed;
      std::printf("mu %.1f: slip work %.3e J, impulse steps of %.0e against adaptive %.2e of V\n",
                  mu, a.result.slip_work.sum(), relative, gap);
      EXPECT_LT(gap, relative);
      if (coarse > 0.0) {
        EXPECT_LT(gap, coarse / 5.0);  // converging, at first order
      }
      coarse = gap;
    }
  }
}

// A straight chain struck head-on with friction is the frictionless chain: no slip arises, the
// tangential impulses stay 0 and the normal ones are the frictionless ones to the bit, for both
// integrators.
TEST(FrictionalImpact, HeadOnChainWithFrictionIsTheFrictionlessChain) {
  const double r = 0.01, m = 0.0327;
  Discs d{.mass = std::vector<double>(6, m),
          .radius = std::vector<double>(6, r),
          .position = Eigen::VectorXd::Zero(18),
          .velocity = Eigen::VectorXd::Zero(18),
          .pairs = {}};
  for (int i = 0; i < 6; ++i) d.position(3 * i) = 2.0 * r * i;
  for (int i = 0; i + 1 < 6; ++i) d.pairs.push_back({i, i + 1});
  d.velocity(0) = 1.0;
  LzbAdaptiveIntegrator adaptive({.tolerance = 1e-9});
  LzbImpulseIntegrator steps({.relative_delta_p = 1e-4});
  for (ImpactIntegrator* integrator :
       {static_cast<ImpactIntegrator*>(&adaptive), static_cast<ImpactIntegrator*>(&steps)}) {
    const DiscsRun with = integrate(d, 0.5, 0.8, *integrator);
    const DiscsRun without = integrate(d, 0.0, 0.8, *integrator);
    EXPECT_EQ(with.result.tangential_impulse, Eigen::VectorXd::Zero(5)) << integrator->name();
    EXPECT_EQ(with.result.impulse, without.result.impulse) << integrator->name();
    EXPECT_EQ(with.velocity, without.velocity) << integrator->name();
  }
}

// mu = 0 with tangential rows: the normal impulse is the frictionless one to the bit, and the
// slip moves only by H_tn P.
TEST(FrictionalImpact, NoFrictionIsTheFrictionlessImpactToTheBit) {
  const PlanarContact c = bar(30.0, 0.0, 0.7, 0.3, 0.0);
  LzbAdaptiveIntegrator integrator({.tolerance = 1e-9});
  const PlanarRun with_rows = integrate(c, integrator);
  const ContactLaw laws[] = {{.stiffness = 1e9, .exponent = 1.5, .restitution = 0.7}};
  const ImpactResult without = integrator.integrate(
      one_by_one(c.h_nn()), Eigen::VectorXd::Constant(1, c.w_n.dot(c.velocity)), laws);
  EXPECT_EQ(with_rows.result.impulse(0), without.impulse(0));
  EXPECT_EQ(with_rows.result.velocity(0), without.velocity(0));
  EXPECT_EQ(with_rows.result.tangential_impulse(0), 0.0);
  EXPECT_DOUBLE_EQ(with_rows.result.slip(0), c.w_t.dot(c.velocity) + c.h_tn() * without.impulse(0));
}

// Friction where it cannot act is refused before any work, naming the field and what is
// allowed.
TEST(FrictionalImpact, BadFrictionInputIsRefused) {
  const PlanarContact c = bar(30.0, 0.3, 0.5, 0.3, 0.0);
  const ContactLaw frictional[] = {{.stiffness = 1e9, .friction = 0.3}};
  const Eigen::VectorXd u = Eigen::VectorXd::Constant(1, -1.0);
  auto message = [](auto&& call) {
    try {
      call();
    } catch (const InvalidInput& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  LzbAdaptiveIntegrator adaptive;
  EXPECT_NE(message([&] {
              adaptive.integrate(one_by_one(c.h_nn()), u, frictional);
            }).find("contact 0's friction"),
            std::string::npos);
  LzbAsynchronousIntegrator steps;
  const std::string unsupported = message([&] { integrate(c, steps); });
  EXPECT_NE(unsupported.find("does not integrate friction"), std::string::npos) << unsupported;
  const ContactLaw negative[] = {{.stiffness = 1e9, .friction = -0.1}};
  EXPECT_NE(message([&] {
              adaptive.integrate(one_by_one(c.h_nn()), u, negative);
            }).find("contact 0: friction mu = -0.1 is invalid; allowed: >= 0"),
            std::string::npos);
  TangentialRows rows{.normal_to_tangent = one_by_one(0.0),
                      .tangent = one_by_one(-1.0),
                      .slip_minus = Eigen::VectorXd::Zero(1),
                      .first_row = {0, 1}};
  EXPECT_NE(message([&] {
              adaptive.integrate(one_by_one(c.h_nn()), u, frictional, rows);
            }).find("H_tt(0, 0)"),
            std::string::npos);
}

}  // namespace
}  // namespace mimpact::numerics
