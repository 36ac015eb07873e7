// The LZB impact problem: the same impact in other coordinates (a non-diagonal mass
// factorized by CHOLMOD), a law it cannot handle, and the relative impulse step.
#include <gtest/gtest.h>

#include "mimpact/common/error.hpp"
#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/linear_relation.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::plugins {
namespace {

using kernel::Index;

std::shared_ptr<LzbLaw> hertz(double e) {
  numerics::ContactLaw law;
  law.stiffness = 1e10;
  law.restitution = e;
  return std::make_shared<LzbLaw>(law);
}

// Three bodies on a line, x = A q for an invertible A: the mass becomes A^T M_x A (not
// diagonal) and the contact rows W_x A. The impact must give the same physical velocities.
TEST(LzbImpactProblem, NonDiagonalMassGivesTheSameImpactAsTheDiagonalOne) {
  const Eigen::Vector3d masses(0.03, 0.05, 0.02), x(0.0, 0.02, 0.04), vx(1.0, 0.0, -0.3);
  const double contact_distance = 0.02;
  Eigen::Matrix3d A;
  A << 1.0, 0.0, 0.0, 0.5, 1.0, 0.0, 0.0, -0.7, 1.0;

  auto diagonal = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  std::vector<std::shared_ptr<kernel::DynamicalSystem>> bodies;
  for (int i = 0; i < 3; ++i) {
    kernel::LagrangianLinearTIDS::Matrices matrices;
    matrices.mass = Eigen::MatrixXd::Constant(1, 1, masses(i));
    bodies.push_back(std::make_shared<kernel::LagrangianLinearTIDS>(
        Eigen::VectorXd::Constant(1, x(i)), Eigen::VectorXd::Constant(1, vx(i)), matrices,
        "body " + std::to_string(i)));
    diagonal->add(bodies.back());
  }
  for (int i = 0; i < 2; ++i)
    diagonal->add(std::make_shared<kernel::Interaction>(
        bodies[i], bodies[i + 1],
        std::make_shared<kernel::LinearRelation>(Eigen::RowVector2d(-1.0, 1.0), -contact_distance),
        hertz(0.9), "c" + std::to_string(i)));

  auto transformed = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  kernel::LagrangianLinearTIDS::Matrices matrices;
  matrices.mass = A.transpose() * masses.asDiagonal() * A;
  const Eigen::Matrix3d A_inverse = A.inverse();
  auto body =
      std::make_shared<kernel::LagrangianLinearTIDS>(A_inverse * x, A_inverse * vx, matrices, "q");
  transformed->add(body);
  for (int i = 0; i < 2; ++i) {
    Eigen::RowVector3d row = Eigen::RowVector3d::Zero();
    row(i) = -1.0;
    row(i + 1) = 1.0;
    transformed->add(std::make_shared<kernel::Interaction>(
        body, std::make_shared<kernel::LinearRelation>(row * A, -contact_distance), hertz(0.9),
        "c" + std::to_string(i)));
  }
  ASSERT_FALSE(transformed->mass_is_diagonal());

  const std::vector<Index> closed{0, 1};
  LzbImpactOptions options;
  options.delta_p = 1e-6;
  LzbImpactProblem a(options), b(options);
  const kernel::ImpactReport by_bodies = a.solve(*diagonal, closed, 0.0);
  const kernel::ImpactReport by_q = b.solve(*transformed, closed, 0.0);
  EXPECT_EQ(by_bodies.result.steps, by_q.result.steps);
  EXPECT_LE((by_bodies.result.impulse - by_q.result.impulse).cwiseAbs().maxCoeff(),
            1e-12 * by_bodies.result.impulse.maxCoeff());
  const Eigen::Vector3d after = A * body->velocity();
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(after(i), bodies[i]->velocity()(0), 1e-11) << "body " << i;
  // momentum of the three bodies, unchanged
  EXPECT_NEAR(masses.dot(after), masses.dot(vx), 1e-15);
}

TEST(LzbImpactProblem, ALawItCannotHandleIsNamed) {
  class NewtonLaw : public kernel::NonSmoothLaw {
   public:
    std::string_view kind() const override { return "newton"; }
  };
  LzbImpactProblem problem;
  try {
    problem.check_law(NewtonLaw(), "wall");
    FAIL();
  } catch (const InvalidInput& error) {
    EXPECT_NE(std::string(error.what())
                  .find("interaction 'wall' has a \"newton\" law, which the "
                        "\"lzb\" impact problem cannot handle"),
              std::string::npos)
        << error.what();
  }
  EXPECT_NO_THROW(problem.check_law(*hertz(1.0), "ok"));
}

TEST(LzbImpactProblem, RelativeStepResolvesWeakAndStrongImpactsAlike) {
  // the same two-body impact at 1 m/s and at 1 mm/s takes the same number of steps
  std::vector<std::int64_t> steps;
  for (double speed : {1.0, 1e-3}) {
    auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
    kernel::LagrangianLinearTIDS::Matrices matrices;
    matrices.mass = Eigen::MatrixXd::Constant(1, 1, 0.03);
    auto a = std::make_shared<kernel::LagrangianLinearTIDS>(
        Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, speed), matrices, "a");
    auto b = std::make_shared<kernel::LagrangianLinearTIDS>(
        Eigen::VectorXd::Constant(1, 0.02), Eigen::VectorXd::Zero(1), matrices, "b");
    system->add(a);
    system->add(b);
    system->add(std::make_shared<kernel::Interaction>(
        a, b, std::make_shared<kernel::LinearRelation>(Eigen::RowVector2d(-1.0, 1.0), -0.02),
        hertz(0.5), "c"));
    LzbImpactOptions options;
    options.relative_delta_p = 1e-3;
    LzbImpactProblem problem(options);
    const kernel::ImpactReport report = problem.solve(*system, std::vector<Index>{0}, 0.0);
    EXPECT_NEAR(report.result.velocity(0), 0.5 * speed, 1e-12 * speed);
    steps.push_back(report.result.steps);
  }
  EXPECT_EQ(steps[0], steps[1]);
}

}  // namespace
}  // namespace mimpact::plugins
