// The modeling classes of the kernel: systems, relations, interactions, the system with its
// global coordinates, and the errors of bad models.
#include <gtest/gtest.h>

#include <cmath>

#include "../support/error_of.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/kernel/lagrangian_ds.hpp"
#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/linear_relation.hpp"
#include "mimpact/kernel/non_smooth_dynamical_system.hpp"
#include "mimpact/kernel/scleronomous_relation.hpp"

namespace mimpact::kernel {
namespace {

// A law of the tests: the kernel itself names none.
class TestLaw : public NonSmoothLaw {
 public:
  std::string_view kind() const override { return "test"; }
};

using testing::error_of;

std::shared_ptr<LagrangianLinearTIDS> point(double x, double v, double m, const std::string& name) {
  LagrangianLinearTIDS::Matrices matrices;
  matrices.mass = MatrixXd::Constant(1, 1, m);
  return std::make_shared<LagrangianLinearTIDS>(VectorXd::Constant(1, x), VectorXd::Constant(1, v),
                                                matrices, name);
}

TEST(LinearTIDS, ForceIsExternalMinusStiffnessAndDamping) {
  LagrangianLinearTIDS::Matrices matrices;
  matrices.mass = Eigen::Matrix2d::Identity();
  matrices.stiffness = Eigen::Matrix2d{{2, -1}, {-1, 2}};
  matrices.damping = 0.5 * Eigen::Matrix2d::Identity();
  matrices.external_force = Eigen::Vector2d(1.0, -3.0);
  LagrangianLinearTIDS system(Eigen::Vector2d(0.1, 0.2), Eigen::Vector2d(1.0, -1.0), matrices, "s");
  VectorXd force(2);
  system.force(0.0, system.position(), system.velocity(), force);
  const Eigen::Vector2d expected = matrices.external_force -
                                   matrices.stiffness * system.position() -
                                   matrices.damping * system.velocity();
  EXPECT_TRUE(force.isApprox(expected, 1e-15));
  EXPECT_TRUE(system.has_force());
  EXPECT_FALSE(point(0, 0, 1, "free")->has_force());
}

TEST(LagrangianDS, CallablesGiveMassAndForce) {
  // a pendulum in its angle: M = m L^2, F = -m g L sin(theta)
  const double m = 2.0, L = 0.5, g = 9.81;
  LagrangianDS pendulum(
      VectorXd::Constant(1, 0.3), VectorXd::Zero(1),
      [&](const VectorXd&, MatrixXd& M) { M(0, 0) = m * L * L; }, "pendulum");
  pendulum.set_internal_force([&](double, const VectorXd& q, const VectorXd&, VectorXd& f) {
    f(0) = m * g * L * std::sin(q(0));
  });
  MatrixXd M(1, 1);
  pendulum.mass(pendulum.position(), M);
  VectorXd F(1);
  pendulum.force(0.0, pendulum.position(), pendulum.velocity(), F);
  EXPECT_DOUBLE_EQ(M(0, 0), m * L * L);
  EXPECT_DOUBLE_EQ(F(0), -m * g * L * std::sin(0.3));
  EXPECT_FALSE(pendulum.mass_is_constant());
}

TEST(BadModels, NonPositiveMassIsNamed) {
  auto system = point(0.0, 0.0, -1.0, "ghost");
  const std::string message = error_of([&] { system->check_mass(); });
  EXPECT_NE(message.find("system 'ghost'"), std::string::npos) << message;
  EXPECT_NE(message.find("positive"), std::string::npos) << message;
}

TEST(BadModels, MassOfTheWrongSizeIsNamed) {
  LagrangianLinearTIDS::Matrices matrices;
  matrices.mass = MatrixXd::Identity(3, 3);
  const std::string message = error_of(
      [&] { LagrangianLinearTIDS(VectorXd::Zero(2), VectorXd::Zero(2), matrices, "wrong"); });
  EXPECT_NE(message.find("3x3; allowed: 2x2"), std::string::npos) << message;
}

TEST(BadModels, JacobianOfTheWrongSizeIsNamed) {
  auto a = point(0.0, 0.0, 1.0, "a"), b = point(1.0, 0.0, 1.0, "b");
  auto relation = std::make_shared<ScleronomousRelation>(
      [](const VectorXd& q) { return q(1) - q(0); },
      [](const VectorXd&, RowVectorXd& row) { row = RowVectorXd::Ones(3); });
  const std::string message =
      error_of([&] { Interaction(a, b, relation, std::make_shared<TestLaw>(), "bad jacobian"); });
  EXPECT_NE(message.find("interaction 'bad jacobian': the Jacobian has 3 entries; allowed: 2"),
            std::string::npos)
      << message;
}

TEST(BadModels, InteractionWithoutALawIsNamed) {
  auto a = point(0.0, 0.0, 1.0, "a");
  const std::string message = error_of([&] {
    Interaction(a, std::make_shared<LinearRelation>(RowVectorXd::Ones(1), 0.0), nullptr, "lawless");
  });
  EXPECT_NE(message.find("interaction 'lawless' has no nonsmooth law"), std::string::npos)
      << message;
}

TEST(BadModels, InitialInterpenetrationBeyondToleranceIsNamed) {
  auto a = point(0.0, 0.0, 1.0, "a"), b = point(0.5, 0.0, 1.0, "b");
  NonSmoothDynamicalSystem system;
  system.add(a);
  system.add(b);
  // radii adding to 0.625 at distance 0.5: 0.125 m of interpenetration
  system.add(std::make_shared<Interaction>(
      a, b, std::make_shared<LinearRelation>(RowVectorXd{{-1.0, 1.0}}, -0.625),
      std::make_shared<TestLaw>(), "overlap"));
  const std::string message = error_of([&] { system.check(1e-9); });
  EXPECT_NE(message.find("interaction 'overlap' starts interpenetrated: gap = -0.125"),
            std::string::npos)
      << message;
  EXPECT_EQ(error_of([&] { system.check(0.2); }), "");
}

TEST(BadModels, InteractionWithASystemNotAddedIsNamed) {
  auto a = point(0.0, 0.0, 1.0, "a"), b = point(1.0, 0.0, 1.0, "stranger");
  NonSmoothDynamicalSystem system;
  system.add(a);
  const std::string message = error_of([&] {
    system.add(std::make_shared<Interaction>(
        a, b, std::make_shared<LinearRelation>(RowVectorXd{{-1.0, 1.0}}, 0.0),
        std::make_shared<TestLaw>(), "c"));
  });
  EXPECT_NE(message.find("'stranger', which is not part of the system"), std::string::npos)
      << message;
}

TEST(NonSmoothDynamicalSystem, GlobalCoordinatesAndJacobians) {
  // a 2-dof system between two points; the contact joins the first point and the second
  // coordinate of the 2-dof system
  auto a = point(0.0, 1.0, 2.0, "a");
  LagrangianLinearTIDS::Matrices matrices;
  matrices.mass = Eigen::Matrix2d{{3.0, 1.0}, {1.0, 2.0}};
  auto body = std::make_shared<LagrangianLinearTIDS>(Eigen::Vector2d(5.0, 2.0),
                                                     Eigen::Vector2d(0.0, -1.0), matrices, "body");
  NonSmoothDynamicalSystem system;
  system.add(a);
  system.add(body);
  const Index j = system.add(std::make_shared<Interaction>(
      a, body, std::make_shared<LinearRelation>(RowVectorXd{{-1.0, 0.0, 1.0}}, -0.5),
      std::make_shared<TestLaw>(), "c"));
  EXPECT_EQ(system.dof(), 3);
  EXPECT_EQ(system.offset(1), 1);
  VectorXd q, v;
  system.gather_state(q, v);
  EXPECT_EQ(q, Eigen::Vector3d(0.0, 5.0, 2.0));
  EXPECT_DOUBLE_EQ(system.gap(j, q), 2.0 - 0.0 - 0.5);
  EXPECT_DOUBLE_EQ(system.velocity(j, q, v), -1.0 - 1.0);
  const Eigen::MatrixXd W = system.jacobian_matrix(std::vector<Index>{j}, q);
  EXPECT_EQ(W, Eigen::Vector3d(-1.0, 0.0, 1.0));
  const Eigen::MatrixXd M = system.mass_matrix(q);
  EXPECT_EQ(M(1, 2), 1.0);
  EXPECT_EQ(M(0, 1), 0.0);
  EXPECT_FALSE(system.mass_is_diagonal());
  EXPECT_EQ(system.interactions_of(1), std::vector<Index>{j});
  system.scatter_state(2.0 * q, v);
  EXPECT_EQ(body->position(), Eigen::Vector2d(10.0, 4.0));
}

TEST(ScleronomousRelation, RateByFiniteDifferenceMatchesTheHessian) {
  // g = |x| - 1 in the plane: v^T (d2g) v = (|v|^2 - (x.v)^2/|x|^2) / |x|
  ScleronomousRelation relation(
      [](const VectorXd& q) { return q.norm() - 1.0; },
      [](const VectorXd& q, RowVectorXd& row) { row = q.transpose() / q.norm(); });
  const Eigen::Vector2d x(0.6, 0.9), v(1.5, -0.4);
  const double exact = (v.squaredNorm() - std::pow(x.dot(v), 2) / x.squaredNorm()) / x.norm();
  EXPECT_NEAR(relation.jacobian_rate(x, v), exact, 1e-6 * std::abs(exact));
}

}  // namespace
}  // namespace mimpact::kernel
