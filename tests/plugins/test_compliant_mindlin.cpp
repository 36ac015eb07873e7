// The compliant integrator with a Mindlin tangential spring under Coulomb's cap
// (numerics::mindlin::Spring; docs/friction.md, section 3) on a sphere striking a flat wall, the
// one contact whose normal stays put, so that the linear relations of the kernel carry it
// exactly: against LAMMPS's `fix wall/gran granular hertz ... tangential mindlin` at its finest
// step, in the limit of a stiff spring against the rigid tangential response's closed form, and
// the ledger of the tangential force's work.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "../support/planar_frictional_impact.hpp"
#include "../support/stop_when_a_contact_opens.hpp"
#include "mimpact/common/error.hpp"
#include "mimpact/kernel/lagrangian_linear_tids.hpp"
#include "mimpact/kernel/linear_relation.hpp"
#include "mimpact/kernel/simulation.hpp"
#include "mimpact/plugins/acceleration_lcp_problem.hpp"
#include "mimpact/plugins/compliant_integrator.hpp"
#include "mimpact/plugins/event_driven_integrator.hpp"
#include "mimpact/plugins/lzb_impact_problem.hpp"
#include "mimpact/plugins/lzb_law.hpp"

namespace mimpact::plugins {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// Steel (E 203 GPa, nu 0.3, 7780 kg/m^3) of radius 5 mm, on a wall of its own material as
// LAMMPS's pair convention has it: F_n = kn sqrt(r delta) delta, kn = 4/3 E/(2 (1 - nu^2)), and
// k_t = kt sqrt(r delta), kt = 8 E/(4 (2 - nu)(1 + nu)); so K = kn sqrt(r) and
// lambda = k_t / (dF_n/d delta) = kt / (1.5 kn), 2 (1 - nu)/(2 - nu).
constexpr double kRadius = 0.005, kYoung = 203e9, kPoisson = 0.3;
const double kMass = 4.0 / 3.0 * std::numbers::pi * std::pow(kRadius, 3) * 7780.0;
const double kNormal = 4.0 / 3.0 * kYoung / (2.0 * (1.0 - kPoisson * kPoisson));
const double kTangential = 8.0 * kYoung / (4.0 * (2.0 - kPoisson) * (1.0 + kPoisson));

numerics::ContactLaw steel_on_steel(double mu, double ratio) {
  return {.stiffness = kNormal * std::sqrt(kRadius),
          .restitution = 1.0,
          .friction = mu,
          .tangential_stiffness_ratio = ratio};
}

struct Outcome {
  Vector6d velocity;  // v (m/s), omega (rad/s)
  double tangential_work = 0.0, normal_work = 0.0;
};

// A sphere touching the wall z = 0 at t = 0, coordinates (x, y, z, and rotations about x, y, z),
// struck with velocity v and spin w until its contact opens: gap z - r, the contact point's slip
// v - r w x n, n = z.
// Through the event-driven scheme's LZB impact instead, with `lzb`.
Outcome strike(const Eigen::Vector3d& v, const Eigen::Vector3d& w, const numerics::ContactLaw& law,
               double tolerance = 1e-12, bool lzb = false) {
  const double inertia = 0.4 * kMass * kRadius * kRadius;
  kernel::LagrangianLinearTIDS::Matrices matrices;
  matrices.mass = Vector6d(kMass, kMass, kMass, inertia, inertia, inertia).asDiagonal();
  Vector6d q = Vector6d::Zero(), velocity;
  q(2) = kRadius;
  velocity << v, w;
  auto body = std::make_shared<kernel::LagrangianLinearTIDS>(q, velocity, matrices, "sphere");
  Eigen::RowVectorXd normal = Eigen::RowVectorXd::Unit(6, 2);
  Eigen::MatrixXd tangents(2, 6);
  tangents << 1, 0, 0, 0, -kRadius, 0, 0, 1, 0, kRadius, 0, 0;
  auto system = std::make_shared<kernel::NonSmoothDynamicalSystem>();
  system->add(body);
  system->add(std::make_shared<kernel::Interaction>(
      body, std::make_shared<kernel::LinearRelation>(normal, -kRadius, tangents),
      std::make_shared<LzbLaw>(law), "wall"));
  CompliantOptions options;
  options.ode.relative_tolerance = tolerance;
  options.ode.absolute_tolerance = 1e-6 * tolerance;
  kernel::Simulation simulation =
      lzb ? kernel::Simulation(system, std::make_unique<EventDrivenIntegrator>(),
                               {.impacts = std::make_unique<LzbImpactProblem>(),
                                .contact_forces = std::make_unique<AccelerationLcpProblem>()})
          : kernel::Simulation(system, std::make_unique<CompliantIntegrator>(options));
  testing::StopWhenAContactOpens opening;
  simulation.add_observer(opening);
  simulation.run(0.0, 1.0);
  if (lzb) return {body->velocity()};
  const kernel::ContactForceHistory& history = *simulation.integrator().contact_force_history();
  return {body->velocity(), history.slip_work(0), history.work(0)};
}

// LAMMPS's velocities and spins, one case a line (tests/data/lammps/README.md).
std::vector<std::vector<double>> lammps_cases() {
  std::ifstream file(std::string(MIMPACT_SOURCE_DIR) +
                     "/tests/data/lammps/sphere_on_wall_mindlin.csv");
  std::string line;
  std::getline(file, line);  // header
  std::vector<std::vector<double>> cases;
  while (std::getline(file, line)) {
    std::stringstream fields(line);
    std::vector<double>& values = cases.emplace_back();
    for (std::string field; std::getline(fields, field, ',');) values.push_back(std::stod(field));
    if (values.size() != 13) throw std::runtime_error("not 13 fields: " + line);
  }
  return cases;
}

// The sphere at incidence 0 to 85 degrees, without spin and with a sideways velocity and a spin
// about every axis (its slip turning in the tangent plane), mu 0.3: v and r omega after the
// impact within 1e-8 of V = 1 m/s of LAMMPS's at dt = 1.5625e-10 s (which its halvings place
// within 1e-10 of their limit).
TEST(CompliantMindlin, SphereOnAWallMeetsLammps) {
  const std::vector<std::vector<double>> cases = lammps_cases();
  ASSERT_EQ(cases.size(), 36u);
  double worst = 0.0;
  const double ratio = kTangential / (1.5 * kNormal);
  for (const std::vector<double>& c : cases) {
    const Outcome got = strike({c[1], c[2], c[3]}, {c[4], c[5], c[6]}, steel_on_steel(0.3, ratio));
    Vector6d lammps;
    lammps << c[7], c[8], c[9], c[10], c[11], c[12];
    Vector6d error = got.velocity - lammps;
    error.tail<3>() *= kRadius;
    worst = std::max(worst, error.cwiseAbs().maxCoeff());
    EXPECT_LT(error.cwiseAbs().maxCoeff(), 1e-8) << "incidence " << c[0] << ", spin " << c[4];
  }
  std::printf("sphere on a wall, Hertz-Mindlin, %zu strikes against LAMMPS: worst %.2e of V\n",
              cases.size(), worst);
}

// As the spring stiffens (lambda x 1 to 10^4) the sphere's rebound at 10 to 60 degrees, mu 0.3,
// tends to the rigid tangential response's closed form (Stronge 2000: slip, then rolling), the
// worst error over the incidences falling with every decade; and the ledger: at e = 1 the kinetic
// energy lost is the tangential force's work (>= 0, the normal force's nil) to 1e-12 of the
// energy.
TEST(CompliantMindlin, StiffSpringTendsToTheRigidResponseAndTheLedgerHolds) {
  const double m = kMass, inertia = 0.4 * m * kRadius * kRadius;
  const double lambda = kTangential / (1.5 * kNormal);
  double previous = 1.0, first = 0.0, worst_ledger = 0.0;
  for (double stiffer : {1.0, 10.0, 100.0, 1e3, 1e4}) {
    double worst = 0.0;
    for (double degrees : {10.0, 20.0, 30.0, 45.0, 60.0}) {
      const double a = degrees * std::numbers::pi / 180.0;
      const Eigen::Vector3d v(std::sin(a), 0.0, -std::cos(a));
      const Outcome got = strike(v, Eigen::Vector3d::Zero(), steel_on_steel(0.3, stiffer * lambda));
      const testing::PlanarOutcome exact =
          testing::planar_frictional_impact({.h_nn = 1.0 / m,
                                             .h_tn = 0.0,
                                             .h_tt = 1.0 / m + kRadius * kRadius / inertia,
                                             .u_n0 = v(2),
                                             .s_0 = v(0),
                                             .mu = 0.3,
                                             .e = 1.0});
      const double vx = v(0) + exact.p_t / m, wy = -kRadius * exact.p_t / inertia;
      worst = std::max(
          {worst, std::abs(got.velocity(0) - vx), kRadius * std::abs(got.velocity(4) - wy)});
      const double before = 0.5 * m * v.squaredNorm();
      const double lost = before - 0.5 * m * got.velocity.head<3>().squaredNorm() -
                          0.5 * inertia * got.velocity.tail<3>().squaredNorm();
      worst_ledger =
          std::max(worst_ledger, std::abs(lost - got.tangential_work - got.normal_work) / before);
      EXPECT_GT(got.tangential_work, 0.0);
    }
    std::printf("spring %g x Mindlin's: worst %.2e of V from the rigid response\n", stiffer, worst);
    EXPECT_LT(worst, previous);
    previous = worst;
    if (first == 0.0) first = worst;
  }
  EXPECT_GT(first, 1e-2);     // the spring matters at Mindlin's own stiffness ...
  EXPECT_LT(previous, 1e-4);  // ... and hardly once 10^4 times stiffer
  std::printf("ledger: lost - work %.1e of the energy\n", worst_ledger);
  EXPECT_LT(worst_ledger, 1e-12);
}

// A spring on an inelastic contact, and a spring given to the LZB impact, are refused before
// any work, naming the field, its value and what is allowed.
TEST(CompliantMindlin, SpringsOnlyWhereIntegrated) {
  numerics::ContactLaw law = steel_on_steel(0.3, 0.8);
  law.restitution = 0.9;
  try {
    strike({0.5, 0.0, -0.5}, Eigen::Vector3d::Zero(), law);
    FAIL() << "accepted";
  } catch (const InvalidInput& error) {
    const std::string text = error.what();
    EXPECT_NE(text.find("tangential_stiffness_ratio = 0.8"), std::string::npos) << text;
    EXPECT_NE(text.find("e = 1"), std::string::npos) << text;
  }
  try {
    strike({0.5, 0.0, -0.5}, Eigen::Vector3d::Zero(), steel_on_steel(0.3, 0.8), 1e-12, true);
    FAIL() << "accepted";
  } catch (const InvalidInput& error) {
    const std::string text = error.what();
    EXPECT_NE(text.find("tangential_stiffness_ratio = 0.8"), std::string::npos) << text;
    EXPECT_NE(text.find("rigid"), std::string::npos) << text;
  }
}

}  // namespace
}  // namespace mimpact::plugins
