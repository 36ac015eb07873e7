// The LZB impact with friction through the kernel (docs/model.md, section 16): a relation's
// tangent rows, the rotation of a body in W, and the impact problem's v+ against the closed
// form of Stronge's slender bar.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "../support/planar_frictional_impact.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/linear_relation.hpp"
#include "mimpact/kernel/scleronomous_relation.hpp"
#include "mimpact/kernel/simulation.hpp"
#include "mimpact/plugins/acceleration_lcp_problem.hpp"
#include "mimpact/plugins/event_driven_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::plugins {
namespace {

using kernel::Index;

// A uniform bar (mass m, length L: I = m L^2 / 12) of coordinates (x, y, angle), its lower end
// A = G - (L/2)(cos, sin) on the floor y = 0: the gap y_A, the slip x_A' (tangent rows when
// `rough`), at angle theta and centre velocity (u, -1), no spin.
struct Bar {
  std::shared_ptr<kernel::NonSmoothDynamicalSystem> system;
  std::shared_ptr<kernel::LagrangianLinearTIDS> body;
};

Bar bar(double theta_degrees, double u, double mu, double e, bool rough = true) {
  const double m = 1.0, length = 1.0, half = 0.5 * length;
  const double theta = theta_degrees * std::numbers::pi / 180.0;
  kernel::LagrangianLinearTIDS::Matrices matrices;
  matrices.mass = Eigen::Vector3d(m, m, m * length * length / 12.0).asDiagonal();
  auto body = std::make_shared<kernel::LagrangianLinearTIDS>(
      Eigen::Vector3d(0.0, half * std::sin(theta), theta), Eigen::Vector3d(u, -1.0, 0.0), matrices,
      "bar");
  auto relation = std::make_shared<kernel::ScleronomousRelation>(
      [half](const Eigen::VectorXd& q) { return q(1) - half * std::sin(q(2)); },
      [half](const Eigen::VectorXd& q, Eigen::RowVectorXd& row) {
        row << 0.0, 1.0, -half * std::cos(q(2));
      });
  if (rough)
    relation->set_tangents(1, [half](const Eigen::VectorXd& q, Eigen::MatrixXd& rows) {
      rows << 1.0, 0.0, half * std::sin(q(2));
    });
  numerics::ContactLaw law{.stiffness = 1e9, .exponent = 1.5, .restitution = e, .friction = mu};
  auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  system->add(body);
  system->add(std::make_shared<kernel::Interaction>(body, relation, std::make_shared<LzbLaw>(law),
                                                    "end A"));
  return {system, body};
}

// The bar's worked cases (halt then reversal, halt then stick, gross slip), solved by the kernel's
// impact problem with the adaptive integrator: v+ = v- + M^-1 (W P + W_t P_t) within 1e-10 of
// the closed form's, for both the body's translation and its rotation.
TEST(FrictionThroughTheKernel, StrongeBarMatchesTheClosedForm) {
  LzbImpactOptions options;
  options.integrator = LzbIntegrator::adaptive;
  options.tolerance = 1e-13;
  struct Case {
    double theta, mu, e, u;
  };
  for (const Case& c : {Case{30, 0.2, 0.5, 0.5}, Case{30, 0.9, 0.5, 0.5}, Case{30, 0.5, 0.5, -0.5},
                        Case{60, 0.3, 0.8, 1.0}}) {
    const Bar b = bar(c.theta, c.u, c.mu, c.e);
    const double theta = c.theta * std::numbers::pi / 180.0;
    const double s = std::sin(theta), co = std::cos(theta);
    const testing::PlanarOutcome exact =
        testing::planar_frictional_impact({.h_nn = 1.0 + 3.0 * co * co,
                                           .h_tn = -3.0 * s * co,
                                           .h_tt = 1.0 + 3.0 * s * s,
                                           .u_n0 = -1.0,
                                           .s_0 = c.u,
                                           .mu = c.mu,
                                           .e = c.e});
    const Eigen::Vector3d expected(c.u + exact.p_t, -1.0 + exact.p_n,
                                   12.0 * (-0.5 * co * exact.p_n + 0.5 * s * exact.p_t));
    LzbImpactProblem problem(options);
    const kernel::ImpactReport report = problem.solve(*b.system, std::vector<Index>{0}, 0.0);
    ASSERT_EQ(report.result.status, numerics::ImpactStatus::terminated);
    const std::string what =
        std::to_string(c.theta) + " deg, mu " + std::to_string(c.mu) + ", u " + std::to_string(c.u);
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(b.body->velocity()(i), expected(i), 1e-10) << what << ", coordinate " << i;
    EXPECT_NEAR(report.result.slip(0), b.body->velocity()(0) + 0.5 * s * b.body->velocity()(2),
                1e-12)
        << what;
  }
}

// Friction on a relation without tangent rows is refused before any work, naming the
// interaction, the field and what is allowed.
TEST(FrictionThroughTheKernel, FrictionWithoutTangentRowsIsRefused) {
  const Bar b = bar(30.0, 0.5, 0.3, 0.5, false);
  LzbImpactOptions options;
  options.integrator = LzbIntegrator::adaptive;
  LzbImpactProblem problem(options);
  try {
    problem.solve(*b.system, std::vector<Index>{0}, 0.0);
    FAIL() << "accepted";
  } catch (const InvalidInput& error) {
    const std::string text = error.what();
    EXPECT_NE(text.find("interaction 'end A'"), std::string::npos) << text;
    EXPECT_NE(text.find("friction"), std::string::npos) << text;
    EXPECT_NE(text.find("tangent rows"), std::string::npos) << text;
  }
  EXPECT_EQ(b.body->velocity(), Eigen::Vector3d(0.5, -1.0, 0.0));  // untouched
}

// A uniform disc (I = m r^2 / 2) on a rough floor under gravity, (x, y, angle), its contact's
// slip s = x' + r angle': at rest it stays, held by m g. Sent sliding at V it slides under
// Coulomb's law, v = V - mu g t while its spin grows by -2 mu g t / r, until its slip stops at
// t1 = V / (3 mu g); then it sticks and rolls on at 2 V / 3 (Routh), the stick's force 0. The
// closed form, to the event tolerance's share of the motion, for mu 0.1 to 0.6.
TEST(FrictionThroughTheKernel, ADiscSentSlidingRollsOnAtTwoThirdsOfItsSpeed) {
  const double m = 0.1, r = 0.01, g = 9.81, end = 0.5;
  double worst = 0.0;
  for (const double speed : {0.0, 1.0})
    for (const double mu : {0.1, 0.3, 0.6}) {
      kernel::LagrangianLinearTIDS::Matrices matrices;
      matrices.mass = Eigen::Vector3d(m, m, 0.5 * m * r * r).asDiagonal();
      matrices.external_force = Eigen::Vector3d(0.0, -m * g, 0.0);
      auto disc = std::make_shared<kernel::LagrangianLinearTIDS>(
          Eigen::Vector3d(0.0, r, 0.0), Eigen::Vector3d(speed, 0.0, 0.0), matrices, "disc");
      auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
      system->add(disc);
      system->add(std::make_shared<kernel::Interaction>(
          disc,
          std::make_shared<kernel::LinearRelation>(Eigen::RowVector3d(0, 1, 0), -r,
                                                   Eigen::MatrixXd(Eigen::RowVector3d(1, 0, r))),
          std::make_shared<LzbLaw>(
              numerics::ContactLaw{.stiffness = 1e9, .restitution = 0.5, .friction = mu}),
          "floor"));
      EventDrivenOptions options;
      options.ode.relative_tolerance = 1e-12;
      options.ode.absolute_tolerance = 1e-14;
      kernel::Simulation simulation(system, std::make_unique<EventDrivenIntegrator>(options),
                                    {.impacts = std::make_unique<LzbImpactProblem>(),
                                     .contact_forces = std::make_unique<AccelerationLcpProblem>()});
      simulation.run(0.0, end);
      const double t1 = speed / (3.0 * mu * g);
      const Eigen::Vector3d expected(
          speed * t1 - 0.5 * mu * g * t1 * t1 + 2.0 * speed / 3.0 * (end - t1), r,
          -mu * g * t1 * t1 / r - 2.0 * speed / (3.0 * r) * (end - t1));
      const Eigen::Vector3d rolling(2.0 * speed / 3.0, 0.0, -2.0 * speed / (3.0 * r));
      const double error = std::max((disc->position() - expected).cwiseAbs().maxCoeff(),
                                    (disc->velocity() - rolling)
                                        .cwiseProduct(Eigen::Vector3d(1, 1, r))
                                        .cwiseAbs()
                                        .maxCoeff());
      worst = std::max(worst, error);
      EXPECT_LT(error, 1e-9) << "V " << speed << ", mu " << mu;
    }
  std::printf("a disc sent sliding on a rough floor: worst %.2e (m, m/s) from the closed form\n",
              worst);
}

}  // namespace
}  // namespace mimpact::plugins
