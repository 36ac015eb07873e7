// The step of the impulse-step integrators, synchronous and asynchronous alike
// (ImpulseStepIntegrator): relative_delta_p makes each impact's delta_p the same share of its
// natural impulse max_j -u_j / H_jj, so that impacts whose strengths differ by orders of
// magnitude are resolved alike. With a linear law the LZB impact is invariant under a scaling of
// the velocities (P and u scale together, the forces' ratios do not change): the same share
// then takes the same steps and gives the same u+ / V, where one fixed delta_p would not.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../support/uniform_chain.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/numerics/lzb_asynchronous_integrator.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace mimpact::numerics {
namespace {

template <class Integrator>
class ImpulseSteps : public ::testing::Test {};
using Kinds = ::testing::Types<LzbImpulseIntegrator, LzbAsynchronousIntegrator>;
TYPED_TEST_SUITE(ImpulseSteps, Kinds);

TEST(NaturalImpulse, IsTheImpulseThatStopsTheFastestContactAlone) {
  const Eigen::VectorXd diagonal = Eigen::Vector3d(40.0, 80.0, 20.0);
  const Eigen::VectorXd u_minus = Eigen::Vector3d(-2.0, -8.0, 1.0);
  EXPECT_DOUBLE_EQ(natural_impulse(diagonal, u_minus), 0.1);  // 8 / 80 beats 2 / 40
}

TYPED_TEST(ImpulseSteps, RelativeDeltaPResolvesEveryStrengthAlike) {
  const int contacts = 5;
  const Eigen::SparseMatrix<double> H = testing::uniform_chain_delassus(contacts, 0.03);
  const std::vector<ContactLaw> laws(contacts,
                                     {.stiffness = 1e6, .exponent = 1.0, .restitution = 0.7});
  const double share = 1e-3;
  TypeParam relative({.relative_delta_p = share});
  std::vector<ImpactResult> results;
  for (double speed : {1e-3, 1.0, 1e3}) {
    Eigen::VectorXd u_minus = Eigen::VectorXd::Zero(contacts);
    u_minus(0) = -speed;
    results.push_back(relative.integrate(H, u_minus, laws));
    ASSERT_EQ(results.back().status, ImpactStatus::terminated);
    const double natural = speed / H.coeff(0, 0);
    EXPECT_DOUBLE_EQ(relative.options().delta_p, share * natural);
    // the step a fixed delta_p of that share takes, to the bit
    TypeParam fixed({.delta_p = share * natural});
    const ImpactResult same = fixed.integrate(H, u_minus, laws);
    EXPECT_EQ(same.steps, results.back().steps);
    EXPECT_EQ(same.velocity, results.back().velocity);
    results.back().velocity /= speed;
  }
  for (const ImpactResult& result : results) {
    EXPECT_EQ(result.steps, results.front().steps);
    EXPECT_LT((result.velocity - results.front().velocity).cwiseAbs().maxCoeff(), 1e-12);
  }
  // one fixed delta_p: the weak impact in a handful of steps, the strong one in a million
  TypeParam fixed({.delta_p = share * 1.0 / H.coeff(0, 0)});
  Eigen::VectorXd weak = Eigen::VectorXd::Zero(contacts);
  weak(0) = -1e-3;
  EXPECT_LT(fixed.integrate(H, weak, laws).steps, results.front().steps / 100);
}

TYPED_TEST(ImpulseSteps, SetDeltaPIsCheckedAndReplacesTheRelativeStep) {
  TypeParam integrator({.relative_delta_p = 1e-3});
  EXPECT_THROW(integrator.set_delta_p(0.0), InvalidInput);
  EXPECT_THROW(integrator.set_delta_p(NAN), InvalidInput);
  integrator.set_delta_p(2e-6);
  EXPECT_FALSE(integrator.options().relative_delta_p);
  const Eigen::MatrixXd H = Eigen::MatrixXd::Constant(1, 1, 50.0);
  const ContactLaw law{.stiffness = 1e6, .exponent = 1.0};
  integrator.integrate(H, Eigen::VectorXd::Constant(1, -1.0), std::span(&law, 1));
  EXPECT_EQ(integrator.options().delta_p, 2e-6);
}

}  // namespace
}  // namespace mimpact::numerics
