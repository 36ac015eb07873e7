// The adaptive LZB integrator (the continuous limit of docs/model.md, section 10) against
// analytic solutions, the exact Hertz chain and the impulse steps.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "../support/hertz_chain_reference.hpp"
#include "../support/uniform_chain.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/numerics/lzb_adaptive_integrator.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace mimpact::numerics {
namespace {

// within_steps_from = 1: the switches kept within the steps (docs/design/adaptive_lzb.md), as a
// packing's impact keeps them; the default locates a lone contact's or a chain's
ImpactResult lone_contact(double h, double u_minus, const ContactLaw& law, double tolerance,
                          std::int64_t within_steps_from = LzbAdaptiveOptions{}.within_steps_from) {
  LzbAdaptiveIntegrator integrator(
      {.tolerance = tolerance, .within_steps_from = within_steps_from});
  const ContactLaw laws[] = {law};
  return integrator.integrate(Eigen::MatrixXd::Constant(1, 1, h),
                              Eigen::VectorXd::Constant(1, u_minus), laws);
}

// Kept within the steps, a bi-stiffness contact's peak (e < 1: its delta goes on at 1/e^2 the
// rate) is settled after the step that holds it, its impulse integrated again: the same
// restitution and peak force, for any exponent (e = 0 and the mono-stiffness release, not
// continuous, are always located).
TEST(AdaptiveLone, WithinTheStepsRestitutionAndPeakForceAreExact) {
  const double h = 1.0 / 0.02, u_minus = -0.7;
  for (double eta : {1.0, 1.5, 2.5})
    for (double e : {0.3, 0.8, 1.0}) {
      const ContactLaw law{.stiffness = 3e9, .exponent = eta, .restitution = e};
      const ImpactResult within = lone_contact(h, u_minus, law, 1e-13, 1);
      const ImpactResult located = lone_contact(h, u_minus, law, 1e-13);
      std::printf("eta %g, e %g: u+ %.3e from -e u-, peak %.3e from located's\n", eta, e,
                  within.velocity(0) + e * u_minus, within.max_force(0) / located.max_force(0) - 1);
      EXPECT_NEAR(within.velocity(0), -e * u_minus, 1e-12) << "eta " << eta << " e " << e;
      EXPECT_NEAR(within.max_force(0) / located.max_force(0), 1.0, 1e-11);
    }
}

// One contact: u+ = -e u- for both compliance models, any exponent (energetic restitution,
// docs/model.md, section 3), and the peak force from the energy of the approach.
TEST(AdaptiveLone, RestitutionAndPeakForceAreExact) {
  const double h = 1.0 / 0.02, u_minus = -0.7;
  for (ComplianceModel model : {ComplianceModel::bi_stiffness, ComplianceModel::mono_stiffness})
    for (double eta : {1.0, 1.5})
      for (double e : {0.0, 0.3, 0.8, 1.0}) {
        const ContactLaw law{.stiffness = 3e9, .exponent = eta, .restitution = e, .model = model};
        const ImpactResult result = lone_contact(h, u_minus, law, 1e-13);
        ASSERT_EQ(result.status, ImpactStatus::terminated);
        EXPECT_NEAR(result.velocity(0), -e * u_minus, 1e-12)
            << enum_name(model) << " eta " << eta << " e " << e;
        // (1/2) u-^2 / h = K delta_M^(1+eta) / (1+eta), F_M = K delta_M^eta
        const double delta_max = std::pow(
            (1.0 + eta) * u_minus * u_minus / (2.0 * h * law.stiffness), 1.0 / (1.0 + eta));
        EXPECT_NEAR(result.max_force(0) / (law.stiffness * std::pow(delta_max, eta)), 1.0, 1e-11);
        EXPECT_EQ(result.residual_energy, 0.0);
      }
}

// A linear bi-stiffness contact is a spring of stiffness K in compression and K / e^2 in
// expansion: the impact lasts (1 + e) pi / 2 / sqrt(h K), the peak at pi / 2 / sqrt(h K).
TEST(AdaptiveLone, LinearSpringDurationIsAQuarterPeriodPerPhase) {
  const double h = 25.0, stiffness = 4e6;
  for (double e : {0.3, 0.8, 1.0}) {
    const ImpactResult result =
        lone_contact(h, -1.0, {.stiffness = stiffness, .exponent = 1.0, .restitution = e}, 1e-13);
    const double quarter = std::numbers::pi / 2.0 / std::sqrt(h * stiffness);
    EXPECT_NEAR(result.duration / ((1.0 + e) * quarter), 1.0, 1e-11) << e;
    EXPECT_NEAR(result.time_of_max_force(0) / quarter, 1.0, 1e-11) << e;
  }
}

using testing::UniformChain;

// For e = 1 the continuous LZB impact is the Hertz chain: at tolerance 1e-10 the adaptive
// integrator lands within 1e-8 m/s of the tests' own integration in time.
TEST(AdaptiveChain, ElasticChainIsTheExactHertzChain) {
  const UniformChain chain;
  const int contacts = chain.contacts();
  const std::vector<ContactLaw> laws(contacts, ContactLaw{.stiffness = chain.stiffness});
  LzbAdaptiveIntegrator integrator({.tolerance = 1e-10});
  const ImpactResult result = integrator.integrate(chain.delassus(), chain.struck(), laws);
  ASSERT_EQ(result.status, ImpactStatus::terminated);
  const Eigen::VectorXd velocity = chain.velocity_after(result.impulse);
  Eigen::VectorXd start = Eigen::VectorXd::Zero(chain.beads);
  start(0) = 1.0;
  const testing::HertzChainOutcome exact =
      testing::integrate_hertz_chain(Eigen::VectorXd::Constant(chain.beads, chain.mass), start,
                                     Eigen::VectorXd::Constant(contacts, chain.stiffness));
  const double error = (velocity - exact.velocity).cwiseAbs().maxCoeff();
  std::printf("C1 beads, tolerance 1e-10: max |v+ - v+_Hertz| = %.3g m/s in %lld steps\n", error,
              (long long)result.steps);
  EXPECT_LE(error, 1e-8);
  EXPECT_NEAR(velocity.sum(), 1.0, 1e-12);         // momentum
  EXPECT_NEAR(velocity.squaredNorm(), 1.0, 1e-9);  // energy
}

// The impulse steps converge to the adaptive result: for e = 1 at first order, so that their
// Richardson extrapolation from delta_p = 2e-6 and 1e-6 lands within 1e-6 m/s of it.
TEST(AdaptiveChain, ElasticChainIsTheLimitOfTheImpulseSteps) {
  const UniformChain chain;
  const int contacts = chain.contacts();
  const Eigen::SparseMatrix<double> H = chain.delassus();
  const Eigen::VectorXd u_minus = chain.struck();
  const std::vector<ContactLaw> laws(contacts, ContactLaw{.stiffness = chain.stiffness});
  LzbAdaptiveIntegrator adaptive({.tolerance = 1e-10});
  const ImpactResult continuous = adaptive.integrate(H, u_minus, laws);
  LzbImpulseIntegrator coarse({.delta_p = 2e-6}), fine({.delta_p = 1e-6});
  const Eigen::VectorXd extrapolated =
      2.0 * fine.integrate(H, u_minus, laws).velocity - coarse.integrate(H, u_minus, laws).velocity;
  const double difference = (continuous.velocity - extrapolated).cwiseAbs().maxCoeff();
  std::printf("C1 beads: adaptive %lld steps, max |u+ - u+_Richardson| = %.3g m/s\n",
              (long long)continuous.steps, difference);
  EXPECT_LE(difference, 1e-6);
}

// At e = 0.6 LZB's re-loading rule dissipates every re-compression: the chain ends as one
// block, every bead at V / 21 (docs/model.md, section 3). The continuous impact reaches it to
// the tolerance; the impulse steps approach it as delta_p shrinks.
TEST(AdaptiveChain, DissipativeChainEndsAsOneBlock) {
  const UniformChain chain;
  const int contacts = chain.contacts();
  const Eigen::SparseMatrix<double> H = chain.delassus();
  const Eigen::VectorXd u_minus = chain.struck();
  for (ComplianceModel model : {ComplianceModel::bi_stiffness, ComplianceModel::mono_stiffness}) {
    const std::vector<ContactLaw> laws(
        contacts, ContactLaw{.stiffness = chain.stiffness, .restitution = 0.6, .model = model});
    LzbAdaptiveIntegrator adaptive({.tolerance = 1e-10});
    const ImpactResult continuous = adaptive.integrate(H, u_minus, laws);
    ASSERT_EQ(continuous.status, ImpactStatus::terminated);
    const Eigen::VectorXd velocity = chain.velocity_after(continuous.impulse);
    const double spread = (velocity.array() - 1.0 / chain.beads).abs().maxCoeff();
    std::printf("%s, e = 0.6: adaptive %lld steps, max |v+ - V/21| = %.3g m/s\n",
                std::string(enum_name(model)).c_str(), (long long)continuous.steps, spread);
    EXPECT_LE(spread, 1e-9);
    if (model == ComplianceModel::bi_stiffness) {  // its switches kept within the steps too
      LzbAdaptiveIntegrator within({.tolerance = 1e-10, .within_steps_from = 1});
      const ImpactResult kept = within.integrate(H, u_minus, laws);
      const double kept_spread =
          (chain.velocity_after(kept.impulse).array() - 1.0 / chain.beads).abs().maxCoeff();
      std::printf("within the steps: %lld steps, max |v+ - V/21| = %.3g m/s\n",
                  (long long)kept.steps, kept_spread);
      EXPECT_LE(kept_spread, 1e-9);
    }
    double previous = INFINITY;
    for (double delta_p : {4e-6, 1e-6}) {
      LzbImpulseIntegrator steps({.delta_p = delta_p});
      const double distance =
          (steps.integrate(H, u_minus, laws).velocity - continuous.velocity).cwiseAbs().maxCoeff();
      EXPECT_LT(distance, previous / 2.0) << delta_p;
      previous = distance;
    }
  }
}

// The work follows the wave: ten times more beads cost about ten times the steps, with as
// many contacts integrated per step, since the contacts ahead of and behind the wave are not
// integrated.
TEST(AdaptiveChain, WorkPerStepDoesNotGrowWithTheChain) {
  std::vector<double> steps, contacts_per_step;
  for (int contacts : {100, 1000}) {
    const UniformChain chain{.beads = contacts + 1};
    const std::vector<ContactLaw> laws(contacts, ContactLaw{.stiffness = chain.stiffness});
    LzbAdaptiveIntegrator adaptive({.tolerance = 1e-6});
    const ImpactResult result = adaptive.integrate(chain.delassus(), chain.struck(), laws);
    ASSERT_EQ(result.status, ImpactStatus::terminated);
    steps.push_back(double(result.steps));
    contacts_per_step.push_back(double(result.contact_steps) / double(result.steps));
    std::printf("%d contacts: %lld steps, %.1f contacts per step\n", contacts,
                (long long)result.steps, contacts_per_step.back());
  }
  EXPECT_LT(steps[1] / steps[0], 12.0);
  EXPECT_LT(contacts_per_step[1] / contacts_per_step[0], 1.5);
}

TEST(AdaptiveInput, BadOptionsAndInputAreRefusedByName) {
  auto message_of = [](auto&& call) {
    try {
      call();
    } catch (const InvalidInput& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  EXPECT_NE(
      message_of([] { LzbAdaptiveIntegrator({.tolerance = 1e-15}); }).find("tolerance = 1e-15"),
      std::string::npos);
  EXPECT_NE(message_of([] { LzbAdaptiveIntegrator({.tolerance = NAN}); }).find("tolerance"),
            std::string::npos);
  LzbAdaptiveIntegrator integrator;
  const ContactLaw laws[] = {ContactLaw{.stiffness = 1e9}};
  EXPECT_NE(message_of([&] {
              integrator.integrate(Eigen::MatrixXd::Constant(1, 1, 1.0),
                                   Eigen::VectorXd::Constant(1, 0.5), laws);
            }).find("no approaching contact"),
            std::string::npos);
  EXPECT_NE(message_of([&] { integrator.set_tolerance(0.5); }).find("tolerance = 0.5"),
            std::string::npos);
}

// The observer sees the impact at every sample_interval: times evenly spaced, impulses
// growing, the peak force of the samples at most the located maximum.
TEST(AdaptiveObserver, SamplesAreEvenlySpacedAndBoundedByTheLocatedPeak) {
  const double h = 50.0;
  LzbAdaptiveIntegrator integrator({.tolerance = 1e-10, .sample_interval = 1e-6});
  const ContactLaw laws[] = {ContactLaw{.stiffness = 3e9, .restitution = 0.8}};
  ImpactHistory history;
  const ImpactResult result = integrator.integrate(
      Eigen::MatrixXd::Constant(1, 1, h), Eigen::VectorXd::Constant(1, -0.7), laws, &history);
  ASSERT_GE(history.time.size(), 50u);
  double peak = 0.0;
  for (std::size_t k = 1; k + 1 < history.time.size(); ++k) {
    EXPECT_NEAR(history.time[k], 1e-6 * double(k), 1e-15);
    EXPECT_GE(history.impulse[k][0], history.impulse[k - 1][0]);
    peak = std::max(peak, history.force[k][0]);
  }
  EXPECT_LE(peak, result.max_force(0) * (1.0 + 1e-12));
  EXPECT_GE(peak, 0.99 * result.max_force(0));
  EXPECT_EQ(history.time.back(), result.duration);
}

}  // namespace
}  // namespace mimpact::numerics
