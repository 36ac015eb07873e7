// The LZB impulse-step integrator against closed forms: two bodies (restitution, Hertz
// contact duration and peak force), symmetry, agreement of sparse and dense H, the active
// set, the observer, and the errors of bad input.
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "../support/error_of.hpp"
#include "../support/uniform_chain.hpp"
#include "mimpact/common/error.hpp"

namespace mimpact::numerics {
namespace {

constexpr double kMass1 = 0.02, kMass2 = 0.05;                        // kg
constexpr double kReducedMass = kMass1 * kMass2 / (kMass1 + kMass2);  // 1/H
constexpr double kSpeed = 0.7;                                        // m/s, approach

ImpactResult two_body_impact(const ContactLaw& law, double delta_p) {
  LzbOptions options;
  options.delta_p = delta_p;
  LzbImpulseIntegrator integrator(options);
  const Eigen::MatrixXd H = Eigen::MatrixXd::Constant(1, 1, 1.0 / kReducedMass);
  const Eigen::VectorXd u_minus = Eigen::VectorXd::Constant(1, -kSpeed);
  return integrator.integrate(H, u_minus, std::span(&law, 1));
}

ContactLaw law_for(double exponent, double restitution, ComplianceModel model) {
  // linear springs get a stiffness of similar contact duration
  return {.stiffness = exponent == 1.0 ? 2e6 : 5e9,
          .exponent = exponent,
          .restitution = restitution,
          .model = model};
}

struct TwoBodyCase {
  double exponent;
  ComplianceModel model;
};

class TwoBodies : public ::testing::TestWithParam<TwoBodyCase> {};

// u+ = -e u- for one contact, for every e. Within a step u is linear and the trapezoidal
// work exact, and the steps end exactly where compression ends and where the energy is
// released: a lone contact comes out exact to round-off, however coarse delta_p.
TEST_P(TwoBodies, OneContactRestitutionIsExactAtAnyDeltaP) {
  const auto [exponent, model] = GetParam();
  const double natural_impulse = kReducedMass * kSpeed;
  for (double e : {0.0, 0.3, 0.8, 1.0}) {
    for (int divisions : {3, 100, 10000}) {
      const ImpactResult result =
          two_body_impact(law_for(exponent, e, model), natural_impulse / divisions);
      ASSERT_EQ(result.status, ImpactStatus::terminated);
      EXPECT_NEAR(result.velocity(0), e * kSpeed, 1e-11 * kSpeed)
          << "e = " << e << ", N = " << divisions;
      // the impulse is the change of relative velocity over H
      EXPECT_NEAR(result.impulse(0), (result.velocity(0) + kSpeed) * kReducedMass,
                  1e-12 * natural_impulse);
    }
  }
}

// For e = 1 the contact is an elastic spring F = K delta^eta: its duration and peak force
// have closed forms (Johnson, "Contact Mechanics", section 11.1), which the time recovered
// from dt = dP / F must reproduce.
TEST_P(TwoBodies, ElasticContactDurationAndPeakForceMatchTheClosedForm) {
  const auto [exponent, model] = GetParam();
  const ContactLaw law = law_for(exponent, 1.0, model);
  const double a = 1.0 + exponent;
  const double max_compression =
      std::pow(a * kReducedMass * kSpeed * kSpeed / (2.0 * law.stiffness), 1.0 / a);
  // T = (2 delta_m / V) * integral_0^1 (1 - x^a)^(-1/2) dx = (2 delta_m / V) B(1/a, 1/2) / a
  const double duration = 2.0 * max_compression / kSpeed * std::tgamma(1.0 / a) *
                          std::sqrt(std::numbers::pi) / (a * std::tgamma(1.0 / a + 0.5));
  const double peak_force = law.stiffness * std::pow(max_compression, exponent);

  const ImpactResult result = two_body_impact(law, kReducedMass * kSpeed / 20000);
  EXPECT_NEAR(result.duration, duration, 2e-3 * duration);
  EXPECT_NEAR(result.max_force(0), peak_force, 1e-3 * peak_force);
  EXPECT_NEAR(result.time_of_max_force(0), duration / 2, 2e-3 * duration);
}

INSTANTIATE_TEST_SUITE_P(
    ModelsAndExponents, TwoBodies,
    ::testing::Values(TwoBodyCase{1.0, ComplianceModel::bi_stiffness},
                      TwoBodyCase{1.5, ComplianceModel::bi_stiffness},
                      TwoBodyCase{1.0, ComplianceModel::mono_stiffness},
                      TwoBodyCase{1.5, ComplianceModel::mono_stiffness}),
    [](const auto& param_info) {
      return std::string(param_info.param.model == ComplianceModel::bi_stiffness ? "bi" : "mono") +
             "_eta" + (param_info.param.exponent == 1.0 ? "1" : "1_5");
    });

ContactLaw hertz(double restitution = 1.0) {
  return {.stiffness = 1e10, .exponent = 1.5, .restitution = restitution};
}

TEST(LzbChain, SparseAndDenseDelassusGiveTheSameImpact) {
  const int contacts = 12;
  const Eigen::SparseMatrix<double> sparse = testing::uniform_chain_delassus(contacts, 0.03);
  const Eigen::MatrixXd dense = sparse;
  Eigen::VectorXd u_minus = Eigen::VectorXd::Zero(contacts);
  u_minus(0) = -1.0;
  const std::vector<ContactLaw> laws(contacts, hertz(0.9));
  LzbImpulseIntegrator integrator({.delta_p = 1e-5});
  const ImpactResult a = integrator.integrate(sparse, u_minus, laws);
  const ImpactResult b = integrator.integrate(dense, u_minus, laws);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.impulse, b.impulse);
  EXPECT_EQ(a.velocity, b.velocity);
  EXPECT_EQ(a.max_force, b.max_force);
  EXPECT_EQ(a.duration, b.duration);
}

TEST(LzbChain, StrikesAtBothEndsGiveASymmetricOutcome) {
  // ties between the two end contacts go to the lower index, yet the result must be the
  // mirror image of itself
  const int contacts = 9;
  const Eigen::SparseMatrix<double> H = testing::uniform_chain_delassus(contacts, 0.03);
  Eigen::VectorXd u_minus = Eigen::VectorXd::Zero(contacts);
  u_minus(0) = u_minus(contacts - 1) = -0.5;
  const std::vector<ContactLaw> laws(contacts, hertz(0.95));
  LzbImpulseIntegrator integrator({.delta_p = 1e-6});
  const ImpactResult result = integrator.integrate(H, u_minus, laws);
  ASSERT_EQ(result.status, ImpactStatus::terminated);
  for (int j = 0; j < contacts; ++j)
    EXPECT_NEAR(result.impulse(j), result.impulse(contacts - 1 - j),
                1e-9 * result.impulse.maxCoeff());
}

// The work of a step follows the contacts in the impact, not the chain's length: the wave
// of a struck chain covers a few contacts at a time.
TEST(LzbChain, WorkPerStepIsIndependentOfChainLength) {
  std::vector<double> contacts_per_step;
  for (int contacts : {100, 1000}) {
    const Eigen::SparseMatrix<double> H = testing::uniform_chain_delassus(contacts, 0.03);
    Eigen::VectorXd u_minus = Eigen::VectorXd::Zero(contacts);
    u_minus(0) = -1.0;
    const std::vector<ContactLaw> laws(contacts, hertz());
    LzbImpulseIntegrator integrator({.delta_p = 1e-4});
    const ImpactResult result = integrator.integrate(H, u_minus, laws);
    ASSERT_EQ(result.status, ImpactStatus::terminated);
    contacts_per_step.push_back(double(result.contact_steps) / double(result.steps));
  }
  EXPECT_LT(contacts_per_step[0], 20.0);
  EXPECT_NEAR(contacts_per_step[1], contacts_per_step[0], 0.2 * contacts_per_step[0]);
}

TEST(LzbChain, ObserverSeesTheStartEverySampleAndTheEnd) {
  const int contacts = 6;
  const Eigen::SparseMatrix<double> H = testing::uniform_chain_delassus(contacts, 0.03);
  Eigen::VectorXd u_minus = Eigen::VectorXd::Zero(contacts);
  u_minus(0) = -1.0;
  const std::vector<ContactLaw> laws(contacts, hertz());
  LzbOptions options{.delta_p = 1e-5, .sample_every = 100, .sampled_contacts = {1, 4}};
  LzbImpulseIntegrator integrator(options);
  ImpactHistory history;
  const ImpactResult result = integrator.integrate(H, u_minus, laws, &history);
  ASSERT_EQ(history.step.size(), std::size_t(result.steps / 100 + 2));
  EXPECT_EQ(history.contacts, (std::vector<Eigen::Index>{1, 4}));
  EXPECT_EQ(history.step.front(), 0);
  EXPECT_EQ(history.velocity.front(), (std::vector<double>{0.0, 0.0}));
  EXPECT_EQ(history.step.back(), result.steps);
  EXPECT_EQ(history.time.back(), result.duration);
  // P grows by delta_p a step, but where a primary's phase ends inside a step
  EXPECT_LE(history.principal_impulse.back(), result.steps * 1e-5 * (1 + 1e-12));
  EXPECT_GT(history.principal_impulse.back(), (result.steps - 20) * 1e-5);
  EXPECT_EQ(history.impulse.back()[1], result.impulse(4));
  for (std::size_t k = 1; k < history.time.size(); ++k) {
    EXPECT_GT(history.time[k], history.time[k - 1]);
    EXPECT_GT(history.principal_impulse[k], history.principal_impulse[k - 1]);
  }
}

TEST(LzbChain, StepLimitIsReported) {
  const Eigen::SparseMatrix<double> H = testing::uniform_chain_delassus(4, 0.03);
  const Eigen::VectorXd u_minus = Eigen::Vector4d(-1.0, 0.0, 0.0, 0.0);
  const std::vector<ContactLaw> laws(4, hertz());
  LzbImpulseIntegrator integrator({.delta_p = 1e-6, .max_steps = 10});
  const ImpactResult result = integrator.integrate(H, u_minus, laws);
  EXPECT_EQ(result.status, ImpactStatus::step_limit);
  EXPECT_EQ(result.steps, 10);
  EXPECT_NE(result.message.find("max_steps"), std::string::npos);
}

// --- the distributing law itself (Nguyen & Brogliato 2011, eqs. 11-13), read off the impulses of
// each step

struct StepRecord {
  std::vector<double> energy, velocity, impulse;
};

class EveryStep : public ImpactObserver {
 public:
  void observe(const ImpactSample& sample) override {
    steps.push_back({{sample.energy.begin(), sample.energy.end()},
                     {sample.velocity.begin(), sample.velocity.end()},
                     {sample.impulse.begin(), sample.impulse.end()}});
  }
  std::vector<StepRecord> steps;  // steps[k]: the state after k steps
};

double increment(const EveryStep& record, std::size_t k, std::size_t j) {
  return record.steps[k + 1].impulse[j] - record.steps[k].impulse[j];
}

// Without stored energy the contacts share a step as dP_j / dP_pi = (K_j / K_pi)(u_j / u_pi)^eta
// (eq. 12), the primary taking delta_p.
TEST(DistributingLaw, NoEnergyStoredFollowsEquation12) {
  const double delta_p = 1e-6;
  const Eigen::MatrixXd H = Eigen::Vector2d(30.0, 50.0).asDiagonal();  // two separate pairs
  const Eigen::VectorXd u_minus = Eigen::Vector2d(-1.0, -0.5);
  const std::vector<ContactLaw> laws = {{.stiffness = 1e9}, {.stiffness = 4e9}};
  EveryStep record;
  LzbImpulseIntegrator({.delta_p = delta_p, .sample_every = 1})
      .integrate(H, u_minus, laws, &record);
  const double p0 = increment(record, 0, 0), p1 = increment(record, 0, 1);
  EXPECT_NEAR(p1 / p0, (4e9 / 1e9) * std::pow(0.5 / 1.0, 1.5), 1e-12);
  EXPECT_DOUBLE_EQ(std::max(p0, p1), delta_p);
}

// A contact entering compression beside a primary with energy E_pi takes
// dP_j = delta_p^(1+eta) c^(1+eta) K_j |u_j|^eta / F_pi^(1+eta) (eq. 13); two contacts with
// energy take dP_j = delta_p F_j / F_pi (eq. 11).
TEST(DistributingLaw, EnteringAndLoadedContactsFollowEquations13And11) {
  const double delta_p = 1e-6;
  const Eigen::SparseMatrix<double> H = testing::uniform_chain_delassus(2, 1.0);
  const Eigen::VectorXd u_minus = Eigen::Vector2d(-1.0, 0.0);
  const std::vector<ContactLaw> laws = {{.stiffness = 1e9}, {.stiffness = 3e9}};
  EveryStep record;
  LzbImpulseIntegrator({.delta_p = delta_p, .sample_every = 1})
      .integrate(H, u_minus, laws, &record);

  std::size_t entering = 0;  // the first step contact 1 takes part in
  while (increment(record, entering, 1) == 0.0) ++entering;
  const StepRecord& before = record.steps[entering];
  ASSERT_EQ(before.energy[1], 0.0);
  ASSERT_LT(before.velocity[1], 0.0);
  const double c = std::pow(2.5, 0.6);
  const double primary_force = laws[0].force_from_energy(before.energy[0]);
  const double expected = std::pow(delta_p, 2.5) * std::pow(c, 2.5) * laws[1].stiffness *
                          std::pow(-before.velocity[1], 1.5) / std::pow(primary_force, 2.5);
  EXPECT_NEAR(increment(record, entering, 1), expected, 1e-12 * expected);
  EXPECT_DOUBLE_EQ(increment(record, entering, 0), delta_p);

  const std::size_t loaded = entering + 5;
  const StepRecord& state = record.steps[loaded];
  ASSERT_GT(state.energy[1], 0.0);
  const double f0 = laws[0].force_from_energy(state.energy[0]);
  const double f1 = laws[1].force_from_energy(state.energy[1]);
  EXPECT_NEAR(increment(record, loaded, 1) / increment(record, loaded, 0), f1 / f0,
              1e-10 * f1 / f0);
}

// --- bad input --------------------------------------------------------------------------

using testing::error_of;

TEST(LzbInput, EveryInvalidInputIsNamed) {
  const Eigen::SparseMatrix<double> H = testing::uniform_chain_delassus(3, 0.03);
  const Eigen::VectorXd u_minus = Eigen::Vector3d(-1.0, 0.0, 0.0);
  const std::vector<ContactLaw> laws(3, hertz());
  auto run = [&](const Eigen::SparseMatrix<double>& h, const Eigen::VectorXd& u,
                 const std::vector<ContactLaw>& l, LzbOptions options = {}) {
    return error_of([&] { LzbImpulseIntegrator(options).integrate(h, u, l); });
  };
  auto has = [](const std::string& message, const std::string& part) {
    return message.find(part) != std::string::npos;
  };

  std::vector<ContactLaw> bad = laws;
  bad[1].stiffness = -1.0;
  EXPECT_TRUE(has(run(H, u_minus, bad), "contact 1: stiffness K = -1"));
  bad = laws;
  bad[2].exponent = 0.0;
  EXPECT_TRUE(has(run(H, u_minus, bad), "contact 2: exponent eta = 0"));
  bad = laws;
  bad[0].restitution = 1.5;
  EXPECT_TRUE(has(run(H, u_minus, bad), "restitution e = 1.5"));

  EXPECT_TRUE(has(run(H, u_minus, laws, {.delta_p = 0.0}), "delta_p = 0"));
  EXPECT_TRUE(has(run(H, u_minus, laws, {.delta_p = -1e-5}), "delta_p = -1e-05"));

  Eigen::SparseMatrix<double> asymmetric = H;
  asymmetric.coeffRef(0, 1) = -10.0;
  EXPECT_TRUE(has(run(asymmetric, u_minus, laws), "symmetric"));

  EXPECT_TRUE(has(run(H, Eigen::Vector3d(0.0, 0.5, 0.0), laws), "no approaching contact"));
  EXPECT_TRUE(has(run(H, Eigen::Vector3d(-1.0, NAN, 0.0), laws), "u_minus(1) = nan"));
  EXPECT_TRUE(has(run(H, Eigen::Vector2d(-1.0, 0.0), laws), "u_minus has 2 entries"));
  EXPECT_TRUE(has(run(H, u_minus, {hertz(), hertz()}), "laws has 2 entries"));

  Eigen::SparseMatrix<double> no_mobility = H;
  no_mobility.coeffRef(2, 2) = 0.0;
  EXPECT_TRUE(has(run(no_mobility, u_minus, laws), "H(2, 2) = 0"));

  EXPECT_TRUE(
      has(run(H, u_minus, laws, {.delta_p = 1e-5, .sampled_contacts = {3}}), "sampled_contacts"));
  LzbOptions fixed;
  fixed.fixed_thresholds = LzbOptions::FixedThresholds{1e-8, -1.0};
  EXPECT_TRUE(has(run(H, u_minus, laws, fixed), "fixed_thresholds.energy = -1"));
  fixed.fixed_thresholds = LzbOptions::FixedThresholds{INFINITY, 1e-8};
  EXPECT_TRUE(has(run(H, u_minus, laws, fixed), "fixed_thresholds.velocity = inf"));
}

TEST(LzbInput, DenseRectangularDelassusIsAnError) {
  const std::vector<ContactLaw> laws(2, hertz());
  const std::string message = error_of([&] {
    LzbImpulseIntegrator().integrate(Eigen::MatrixXd::Identity(2, 3), Eigen::Vector2d(-1, 0), laws);
  });
  EXPECT_NE(message.find("H is 2x3"), std::string::npos) << message;
}

}  // namespace
}  // namespace mimpact::numerics
