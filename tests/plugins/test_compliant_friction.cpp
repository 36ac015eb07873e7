// The compliant integrator with Coulomb friction and a rigid tangential response (docs/model.md,
// section 16) against the closed forms of a planar single-contact impact (Stronge 2000): a
// sphere striking a flat obliquely, with and without spin, and Stronge's slender bar, whose slip
// halts and sticks or reverses; its ledger books the slip's work.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "../support/planar_frictional_impact.hpp"
#include "../support/stop_when_a_contact_opens.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/linear_relation.hpp"
#include "mimpact/kernel/scleronomous_relation.hpp"
#include "mimpact/kernel/simulation.hpp"
#include "mimpact/plugins/compliant_integrator.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::plugins {
namespace {

// One planar body of coordinates (x, y, angle) touching the floor y = 0 at t = 0 through a
// linear relation (the frozen configuration): gap C q + e, slip along x with tangent row T.
struct Strike {
  Eigen::Vector3d mass;        // kg, kg, kg m^2
  Eigen::Vector3d position;    // m, m, rad
  Eigen::Vector3d velocity;    // m/s, m/s, rad/s
  Eigen::RowVector3d normal;   // C
  Eigen::RowVector3d tangent;  // T
  numerics::ContactLaw law;
};

struct Outcome {
  Eigen::Vector3d velocity;
  double tangential_impulse = 0.0, slip_work = 0.0, work = 0.0, stored = 0.0;
};

CompliantOptions tight() {
  CompliantOptions options;
  options.ode.relative_tolerance = 1e-12;
  options.ode.absolute_tolerance = 1e-16;
  options.overlap_resolution = 1e-12;
  return options;
}

// Integrates the strike until its contact opens.
Outcome strike(const Strike& s) {
  kernel::LagrangianLinearTIDS::Matrices matrices;
  matrices.mass = s.mass.asDiagonal();
  auto body =
      std::make_shared<kernel::LagrangianLinearTIDS>(s.position, s.velocity, matrices, "body");
  auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  system->add(body);
  system->add(std::make_shared<kernel::Interaction>(
      body,
      std::make_shared<kernel::LinearRelation>(s.normal, -s.normal.dot(s.position),
                                               Eigen::MatrixXd(s.tangent)),
      std::make_shared<LzbLaw>(s.law), "floor"));
  kernel::Simulation simulation(system, std::make_unique<CompliantIntegrator>(tight()));
  testing::StopWhenAContactOpens opening;
  simulation.add_observer(opening);
  simulation.run(0.0, 1.0);
  const kernel::ContactForceHistory& history = *simulation.integrator().contact_force_history();
  const bool rubs = history.slip_work.size() > 0;  // empty where no contact has friction
  return {body->velocity(), rubs ? history.tangential_impulse(0, 0) : 0.0,
          rubs ? history.slip_work(0) : 0.0, history.work(0), history.stored_energy(0)};
}

double kinetic(const Strike& s, const Eigen::Vector3d& v) {
  return 0.5 * v.dot(s.mass.cwiseProduct(v));
}

// v+ = v- + M^-1 (C^T p_n + T^T p_t) from the closed form's impulses.
Eigen::Vector3d closed_form(const Strike& s, testing::PlanarOutcome& exact) {
  const Eigen::Vector3d inverse = s.mass.cwiseInverse();
  const double h_nn = s.normal.cwiseProduct(inverse.transpose()).dot(s.normal);
  const double h_tn = s.tangent.cwiseProduct(inverse.transpose()).dot(s.normal);
  const double h_tt = s.tangent.cwiseProduct(inverse.transpose()).dot(s.tangent);
  exact = testing::planar_frictional_impact({.h_nn = h_nn,
                                             .h_tn = h_tn,
                                             .h_tt = h_tt,
                                             .u_n0 = s.normal.dot(s.velocity),
                                             .s_0 = s.tangent.dot(s.velocity),
                                             .mu = s.law.friction,
                                             .e = s.law.restitution});
  return s.velocity +
         inverse.cwiseProduct(s.normal.transpose() * exact.p_n + s.tangent.transpose() * exact.p_t);
}

// A solid sphere (I = 2/5 m r^2) strikes a flat at 1 m/s at incidence 0 to 89 degrees from the
// normal, with no spin, top-spin or back-spin, mu 0 to 1, e 1 and 0.5: gross slip (the slip
// reduced by mu (1 + e) v_n (1 + m r^2 / I)) or stick (rolling, v_t+ = 5/7 v_t- without spin),
// each to 1e-10 of the speed in velocity and r omega.
TEST(CompliantFriction, SphereOnAFlatMeetsTheClosedForm) {
  const double m = 0.01, r = 0.01, inertia = 0.4 * m * r * r;
  double worst = 0.0;
  int stuck = 0, cases = 0;
  for (double e : {1.0, 0.5})
    for (double mu : {0.0, 0.1, 0.3, 0.6, 1.0})
      for (double incidence : {0.0, 10.0, 30.0, 45.0, 60.0, 80.0, 89.0})
        for (double spin : {0.0, 40.0, -150.0}) {
          const double a = incidence * std::numbers::pi / 180.0;
          const Strike s{.mass = {m, m, inertia},
                         .position = {0.0, r, 0.0},
                         .velocity = {std::sin(a), -std::cos(a), spin},
                         .normal = {0.0, 1.0, 0.0},
                         .tangent = {1.0, 0.0, r},
                         .law = {.stiffness = 5e9, .restitution = e, .friction = mu}};
          testing::PlanarOutcome exact;
          const Eigen::Vector3d expected = closed_form(s, exact);
          const Outcome got = strike(s);
          const Eigen::Vector3d error =
              (got.velocity - expected).cwiseProduct(Eigen::Vector3d(1, 1, r));
          worst = std::max(worst, error.cwiseAbs().maxCoeff());
          EXPECT_LT(error.cwiseAbs().maxCoeff(), 1e-10)
              << "e " << e << ", mu " << mu << ", incidence " << incidence << ", spin " << spin;
          EXPECT_NEAR(got.tangential_impulse, exact.p_t, 1e-10 * m);
          stuck += std::abs(expected(0) + r * expected(2)) < 1e-12;
          ++cases;
        }
  std::printf("sphere on a flat, %d strikes (%d ending rolling): worst error %.2e of V\n", cases,
              stuck, worst);
  EXPECT_GT(stuck, 20);  // both regimes are met
  EXPECT_LT(stuck, cases - 20);
}

// Stronge's slender bar (m = 1 kg, L = 1 m) striking the floor at 30 and 60 degrees, its lower
// end sliding at u: a slip that halts and reverses, halts and sticks, or never halts; e 1, 0.8
// and 0.5. The bar's velocity and spin to 1e-10 of the closed form's, and the ledger: the kinetic
// energy lost is the normal and the slip's work, the slip's >= 0 (at e = 1, all of the loss).
TEST(CompliantFriction, StrongeBarMatchesTheClosedFormAndBooksTheSlip) {
  struct Case {
    double theta, mu, e, u;
  };
  double worst = 0.0, worst_ledger = 0.0;
  for (const Case& c : {Case{30, 0.2, 0.5, 0.5}, Case{30, 0.9, 0.5, 0.5}, Case{30, 0.5, 0.5, -0.5},
                        Case{60, 0.3, 0.8, 1.0}, Case{30, 0.2, 1.0, 0.5}, Case{30, 0.9, 1.0, 0.5},
                        Case{45, 0.4, 1.0, -0.3}}) {
    const double theta = c.theta * std::numbers::pi / 180.0, half = 0.5;
    const Strike s{.mass = {1.0, 1.0, 1.0 / 12.0},
                   .position = {0.0, half * std::sin(theta), theta},
                   .velocity = {c.u, -1.0, 0.0},
                   .normal = {0.0, 1.0, -half * std::cos(theta)},
                   .tangent = {1.0, 0.0, half * std::sin(theta)},
                   .law = {.stiffness = 1e9, .restitution = c.e, .friction = c.mu}};
    testing::PlanarOutcome exact;
    const Eigen::Vector3d expected = closed_form(s, exact);
    const Outcome got = strike(s);
    const double error = (got.velocity - expected).cwiseAbs().maxCoeff();
    worst = std::max(worst, error);
    EXPECT_LT(error, 1e-10) << c.theta << " deg, mu " << c.mu << ", e " << c.e << ", u " << c.u;
    const double lost = kinetic(s, s.velocity) - kinetic(s, got.velocity);
    const double imbalance = std::abs(lost - (got.work + got.slip_work - got.stored));
    worst_ledger = std::max(worst_ledger, imbalance / kinetic(s, s.velocity));
    EXPECT_LT(imbalance, 1e-12 * kinetic(s, s.velocity));
    EXPECT_GE(got.slip_work, 0.0);
    if (c.e == 1.0) {
      EXPECT_NEAR(got.slip_work, lost, 1e-9 * kinetic(s, s.velocity));
    }
  }
  std::printf(
      "Stronge's bar, frozen and compliant: worst error %.2e m/s, ledger %.1e of the "
      "energy\n",
      worst, worst_ledger);
}

// Friction on a relation whose rows move with the bodies is refused before any work, naming the
// field, its value and what is allowed.
TEST(CompliantFriction, FrictionNeedsConstantRows) {
  auto body = std::make_shared<kernel::LagrangianLinearTIDS>(
      Eigen::Vector3d(0, 0.01, 0), Eigen::Vector3d(0, -1, 0),
      kernel::LagrangianLinearTIDS::Matrices{.mass = Eigen::Matrix3d::Identity()}, "body");
  auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  system->add(body);
  auto relation = std::make_shared<kernel::ScleronomousRelation>(
      [](const Eigen::VectorXd& q) { return q(1) - 0.01; },
      [](const Eigen::VectorXd&, Eigen::RowVectorXd& row) { row << 0.0, 1.0, 0.0; });
  relation->set_tangents(
      1, [](const Eigen::VectorXd&, Eigen::MatrixXd& rows) { rows << 1.0, 0.0, 0.01; });
  system->add(std::make_shared<kernel::Interaction>(
      body, relation,
      std::make_shared<LzbLaw>(numerics::ContactLaw{.stiffness = 1e9, .friction = 0.3}), "floor"));
  kernel::Simulation simulation(system, std::make_unique<CompliantIntegrator>());
  try {
    simulation.run(0.0, 1.0);
    FAIL() << "accepted";
  } catch (const InvalidInput& error) {
    const std::string text = error.what();
    EXPECT_NE(text.find("friction"), std::string::npos) << text;
    EXPECT_NE(text.find("0.3"), std::string::npos) << text;
    EXPECT_NE(text.find("linear"), std::string::npos) << text;
  }
}

}  // namespace
}  // namespace mimpact::plugins
