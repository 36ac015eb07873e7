// Every impact integrator through the same physics (one typed suite, as Drake's generic
// integrator test): a lone contact restores u+ = -e u-; chain C1 converges to the exact Hertz
// chain as the accuracy asked tightens; momentum is conserved to round-off and energy within the
// accuracy asked; the three ways of giving H (sparse, dense, the Delassus object) are one
// impact; and an impact that overflows double precision is an error naming the integrator.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "../support/hertz_chain_reference.hpp"
#include "../support/integrator_kinds.hpp"
#include "../support/uniform_chain.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/numerics/delassus.hpp"

namespace mimpact::numerics {
namespace {

using testing::Accuracy;

template <class Kind>
class ImpactIntegrators : public ::testing::Test {};
TYPED_TEST_SUITE(ImpactIntegrators, testing::ImpactIntegratorKinds, testing::KindNames);

using ChainC1 = testing::UniformChain;

// One contact between 20 g and 50 g approaching at 0.7 m/s, for both compliance models, a
// linear and a Hertz law and every restitution: u+ = -e u-, exactly for the synchronous steps
// (a lone contact's steps end where its phases end), within the accuracy asked for the others.
TYPED_TEST(ImpactIntegrators, LoneContactRestoresItsRestitution) {
  const double reduced_mass = 0.02 * 0.05 / 0.07, speed = 0.7;
  const Eigen::MatrixXd H = Eigen::MatrixXd::Constant(1, 1, 1.0 / reduced_mass);
  const Eigen::VectorXd u_minus = Eigen::VectorXd::Constant(1, -speed);
  const double level = TypeParam::kFine;
  const double bound = TypeParam::kLoneContactExact ? 1e-11 : level;
  for (ComplianceModel model : {ComplianceModel::bi_stiffness, ComplianceModel::mono_stiffness})
    for (double exponent : {1.0, 1.5})
      for (double e : {0.0, 0.3, 0.8, 1.0}) {
        const ContactLaw law{.stiffness = exponent == 1.0 ? 2e6 : 5e9,
                             .exponent = exponent,
                             .restitution = e,
                             .model = model};
        const auto integrator =
            TypeParam::make({.level = level, .natural_impulse = reduced_mass * speed});
        const ImpactResult result = integrator->integrate(H, u_minus, std::span(&law, 1));
        ASSERT_EQ(result.status, ImpactStatus::terminated);
        const std::string what = std::string(enum_name(model)) + ", eta " +
                                 std::to_string(exponent) + ", e " + std::to_string(e);
        EXPECT_NEAR(result.velocity(0), e * speed, bound * speed) << what;
        // what the contact took from the bodies less what it stores is what it dissipated
        const double lost = 0.5 * reduced_mass * speed * speed * (1.0 - e * e);
        EXPECT_NEAR(result.work(0) - result.stored_energy(0), lost,
                    2.0 * bound * reduced_mass * speed * speed)
            << what;
      }
}

// C1 against the exact Hertz chain (Boost.Odeint at 1e-12): the largest error of the beads'
// velocities falls by at least 25 when the accuracy asked is 100 times tighter (first order
// for the steps of impulse; the adaptive integrator's error follows its tolerance), and at the
// finest it is within 10 times the level of the striker's speed.
TYPED_TEST(ImpactIntegrators, ChainC1ConvergesToTheExactHertzChain) {
  const ChainC1 chain;
  const std::vector<ContactLaw> laws(chain.contacts(), ContactLaw{.stiffness = chain.stiffness});
  Eigen::VectorXd start = Eigen::VectorXd::Zero(chain.beads);
  start(0) = 1.0;
  const testing::HertzChainOutcome exact =
      testing::integrate_hertz_chain(Eigen::VectorXd::Constant(chain.beads, chain.mass), start,
                                     Eigen::VectorXd::Constant(chain.contacts(), chain.stiffness));
  std::vector<double> errors;
  for (double level : {TypeParam::kFine * 100.0, TypeParam::kFine}) {
    const auto integrator = TypeParam::make({.level = level, .natural_impulse = chain.mass});
    const ImpactResult result = integrator->integrate(chain.delassus(), chain.struck(), laws);
    ASSERT_EQ(result.status, ImpactStatus::terminated);
    errors.push_back((chain.velocity_after(result.impulse) - exact.velocity).cwiseAbs().maxCoeff());
    std::printf("%s at %.0e: max |v+ - v+_Hertz| = %.3e m/s, %lld steps\n", TypeParam::kName, level,
                errors.back(), static_cast<long long>(result.steps));
  }
  EXPECT_GT(errors[0], 25.0 * errors[1]);
  EXPECT_LT(errors[1], 10.0 * TypeParam::kFine);
}

// Momentum to 1e-12 of the striker's, whatever the accuracy; for e = 1 the kinetic energy
// within the accuracy asked, for e < 1 strictly less.
TYPED_TEST(ImpactIntegrators, MomentumIsConservedAndEnergyNeverGained) {
  const ChainC1 chain;
  for (double e : {1.0, 0.7, 0.0})
    for (double level : {TypeParam::kCoarse, TypeParam::kStandard}) {
      const std::vector<ContactLaw> laws(
          chain.contacts(), ContactLaw{.stiffness = chain.stiffness, .restitution = e});
      const auto integrator = TypeParam::make({.level = level, .natural_impulse = chain.mass});
      const ImpactResult result = integrator->integrate(chain.delassus(), chain.struck(), laws);
      ASSERT_EQ(result.status, ImpactStatus::terminated);
      const Eigen::VectorXd v = chain.velocity_after(result.impulse);
      EXPECT_NEAR(v.sum(), 1.0, 1e-12) << "e " << e << ", level " << level;
      const double energy = v.squaredNorm();  // relative to the striker's
      if (e == 1.0)
        EXPECT_NEAR(energy, 1.0, level) << "level " << level;
      else
        EXPECT_LT(energy, 1.0) << "e " << e << ", level " << level;
    }
}

// Where an integrator is reaches its observer whatever it samples (a progress meter's clock
// and time limit): at every step of the adaptive integrator, whose steps may advance no sample
// time, and every kProgressSteps steps of the impulse steps, in order.
class ProgressCount : public ImpactObserver {
 public:
  void observe(const ImpactSample& /*sample*/) override {}
  void progressed(const ImpactProgress& where) override {
    ordered = ordered && where.step > last_step;
    last_step = where.step;
    ++calls;
  }
  std::int64_t calls = 0, last_step = 0;
  bool ordered = true;
};

TYPED_TEST(ImpactIntegrators, WhereItIsReachesTheObserverWhateverItSamples) {
  const ChainC1 chain;
  const std::vector<ContactLaw> laws(chain.contacts(), ContactLaw{.stiffness = chain.stiffness});
  const auto integrator =
      TypeParam::make({.level = TypeParam::kFine, .natural_impulse = chain.mass});
  ProgressCount progress;
  const ImpactResult result =
      integrator->integrate(chain.delassus(), chain.struck(), laws, &progress);
  ASSERT_EQ(result.status, ImpactStatus::terminated);
  const std::int64_t expected =
      TypeParam::kStepsOfImpulse ? result.steps / ImpactObserver::kProgressSteps : result.steps;
  EXPECT_GE(expected, 1) << result.steps << " steps";
  EXPECT_EQ(progress.calls, expected);
  EXPECT_TRUE(progress.ordered);
  EXPECT_LE(progress.last_step, result.steps);
}

// H sparse, H dense and the Delassus object built from W and M^-1 give one impact, to the bit.
TYPED_TEST(ImpactIntegrators, TheThreeFormsOfTheInputAreOneImpact) {
  const ChainC1 chain;
  const std::vector<ContactLaw> laws(chain.contacts(),
                                     ContactLaw{.stiffness = chain.stiffness, .restitution = 0.8});
  // W: contact j is the gap velocity v_(j+1) - v_j
  std::vector<Eigen::Triplet<double>> entries;
  for (int j = 0; j < chain.contacts(); ++j) {
    entries.emplace_back(j, j, -1.0);
    entries.emplace_back(j + 1, j, 1.0);
  }
  Eigen::SparseMatrix<double> W(chain.beads, chain.contacts());
  W.setFromTriplets(entries.begin(), entries.end());
  const Delassus delassus(W, Eigen::VectorXd::Constant(chain.beads, 1.0 / chain.mass));
  const Accuracy accuracy{.level = TypeParam::kCoarse, .natural_impulse = chain.mass};
  const ImpactResult sparse =
      TypeParam::make(accuracy)->integrate(chain.delassus(), chain.struck(), laws);
  const ImpactResult dense =
      TypeParam::make(accuracy)->integrate(Eigen::MatrixXd(chain.delassus()), chain.struck(), laws);
  const ImpactResult from_bodies =
      TypeParam::make(accuracy)->integrate(delassus, chain.struck(), laws);
  ASSERT_TRUE(delassus.H().isApprox(chain.delassus(), 0.0));
  EXPECT_EQ(sparse.impulse, dense.impulse);
  EXPECT_EQ(sparse.impulse, from_bodies.impulse);
  EXPECT_EQ(sparse.velocity, from_bodies.velocity);
  EXPECT_EQ(sparse.steps, from_bodies.steps);
}

// Finite inputs can overflow: a law of K = 1e-320 N/m^0.01 lets two bodies approaching at
// 1 m/s sink about 1e314 m into each other, for as many seconds. The base's check refuses the
// result, naming the integrator, whichever it is, and at once: the asynchronous steps' clock
// past double precision ran to max_steps before, a billion kicks in 86 s.
TYPED_TEST(ImpactIntegrators, AnOverflowIsAnErrorNamingTheIntegrator) {
  const double mass = 0.0326, speed = 1.0;  // kg, m/s
  const ContactLaw law{.stiffness = 1e-320, .exponent = 0.01, .restitution = 1.0};
  const auto integrator =
      TypeParam::make({.level = TypeParam::kCoarse, .natural_impulse = mass * speed});
  try {
    const ImpactResult result =
        integrator->integrate(Eigen::MatrixXd::Constant(1, 1, 2.0 / mass),
                              Eigen::VectorXd::Constant(1, -speed), std::span(&law, 1));
    ADD_FAILURE() << "no error; duration " << result.duration << " s, max force "
                  << result.max_force(0) << " N";
  } catch (const InvalidInput& error) {
    ADD_FAILURE() << "refused as input: " << error.what();
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("overflowed double precision"), std::string::npos) << message;
    EXPECT_NE(message.find(std::string(integrator->name())), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace mimpact::numerics
