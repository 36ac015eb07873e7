// Issue 46: beads that turn and rub in packing scenes (contact.friction, a striker's offset and
// spin, bead lists with velocities and spins), through the kernel's LZB impact. A lone contact
// against its closed form; a packing's momentum, angular momentum and energy ledger.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>

#include "mimpact/common/error.hpp"
#include "mimpact/granular/energy_ledger.hpp"
#include "packing_runs.hpp"

namespace mimpact::testing {
namespace {

using Eigen::Vector3d;

// A body at one side of a lone contact: a sphere, or a wall (infinite mass).
struct Side {
  double mass = std::numeric_limits<double>::infinity(), radius = 0.0;
  Vector3d velocity = Vector3d::Zero(), spin = Vector3d::Zero();
  double inertia() const { return 0.4 * mass * radius * radius; }
};

// The closed form of a lone contact between two solid spheres (or a wall and a sphere), n from
// the first to the second, with Coulomb's mu and restitution e. Its normal and tangential
// impulses do not couple (H_tn = 0, H_tt = (1/m1 + 1/m2 + r1^2/I1 + r2^2/I2) identity), so the
// slip keeps its direction: P_n = (1 + e) |u_n| / H_nn, and P_t = -s / H_tt if that lies in
// the cone (the contact ends stuck), else -mu P_n s / |s| (Stronge, "Impact Mechanics", 2000,
// section 5.2). Writes both sides' velocities after.
void lone_contact(const Vector3d& n, double mu, double e, Side& first, Side& second) {
  const Vector3d u = second.velocity + second.spin.cross(-second.radius * n) - first.velocity -
                     first.spin.cross(first.radius * n);
  const double u_n = n.dot(u);
  const Vector3d s = u - u_n * n;
  const double h_nn = 1.0 / first.mass + 1.0 / second.mass;
  double h_tt = h_nn + second.radius * second.radius / second.inertia();
  if (std::isfinite(first.mass)) h_tt += first.radius * first.radius / first.inertia();
  const double p_n = (1.0 + e) * -u_n / h_nn;
  const Vector3d p_t =
      s.norm() <= mu * p_n * h_tt ? Vector3d(-s / h_tt) : Vector3d(-mu * p_n * s.normalized());
  const Vector3d J = p_n * n + p_t;  // on the second body
  second.velocity += J / second.mass;
  second.spin += (-second.radius * n).cross(J) / second.inertia();
  if (!std::isfinite(first.mass)) return;
  first.velocity -= J / first.mass;
  first.spin += (first.radius * n).cross(-J) / first.inertia();
}

Vector3d padded(const Eigen::VectorXd& v) {
  Vector3d p = Vector3d::Zero();
  p.head(v.size()) = v;
  return p;
}

// A body's velocity and spin after the run, as 3-vectors.
Side after(const PackingCase& run, Eigen::Index body) {
  const packings::PackingModel& model = run.model;
  const granular::ImpactOutcome& impact = run.run.impact;
  Side side{.mass = model.mass(model.dimension * body), .radius = model.radius(body)};
  side.velocity = padded(model.of(impact.velocity_after, body));
  const granular::Rotation& rotation = *model.rotation;
  if (rotation.components == 1)
    side.spin.z() = impact.angular_velocity_after(body);
  else
    side.spin = impact.angular_velocity_after.segment<3>(3 * body);
  return side;
}

// The largest difference of velocities (m/s) and of spins times radii (m/s) of two sides.
double difference(const Side& a, const Side& b) {
  return std::max((a.velocity - b.velocity).cwiseAbs().maxCoeff(),
                  a.radius * (a.spin - b.spin).cwiseAbs().maxCoeff());
}

// One bead listed at the origin in `dimension`, in a scratch directory; the scene's path.
std::filesystem::path one_bead(int dimension) {
  const auto directory = std::filesystem::temp_directory_path() /
                         ("mimpact_test_packing_friction_" + std::to_string(dimension));
  std::filesystem::create_directories(directory);
  std::ofstream(directory / "one.csv")
      << (dimension == 2 ? "x,y,radius\n0,0,0.005\n" : "x,y,z,radius\n0,0,0,0.005\n");
  return directory;
}

TEST(PackingFriction, AnOffCentreSpinningStrikerOnALoneBeadMeetsTheClosedForm) {
  const std::string directory = one_bead(2).string();
  double worst = 0.0;
  int cases = 0, stuck = 0;
  for (double mu : {0.0, 0.05, 0.2, 0.5, 1.0})
    for (double offset : {0.0, 0.002, 0.006, 0.0099})  // of the radii's sum 0.01 m
      for (double spin : {0.0, 40.0, -300.0})          // rad/s; 300 R = 1.5 V
        for (double e : {1.0, 0.5}) {
          const PackingCase run = run_packing(
              "{" + kSteel + R"(, "beads": {"file": "one.csv"}, "strikers": [{"target": [0],
              "radius": 0.005, "velocity": [1, 0], "offset": )" +
                  std::to_string(offset) + R"(, "spin": )" + std::to_string(spin) +
                  R"(}], "contact": {"restitution": )" + std::to_string(e) + R"(, "friction": )" +
                  std::to_string(mu) +
                  R"(}, "impact": {"integrator": "adaptive", "tolerance": 1e-12},
              "configuration_check": {"enabled": false}})",
              directory);
          if (!run.model.rotation) continue;  // mu = 0 without spin: nothing turns
          Side bead = after(run, 0), striker = after(run, 1);
          Side bead_expected{.mass = bead.mass, .radius = bead.radius};
          Side striker_expected{.mass = striker.mass, .radius = striker.radius};
          striker_expected.velocity = Vector3d::UnitX();
          striker_expected.spin.z() = spin;
          lone_contact(padded(run.model.contacts[0].normal), mu, e, bead_expected,
                       striker_expected);
          worst = std::max(
              {worst, difference(bead, bead_expected), difference(striker, striker_expected)});
          ++cases;
          if (mu > 0.0 && std::abs(run.run.impact.result.slip(0)) < 1e-9) ++stuck;
        }
  std::printf("%d oblique strikes (%d ending stuck): worst difference %.3e of V\n", cases, stuck,
              worst);
  EXPECT_GT(stuck, 10);
  EXPECT_LT(worst, 1e-10);
}

TEST(PackingFriction, InSpaceTheSlipTurnsWithTheSpinAndMeetsTheClosedForm) {
  const std::string directory = one_bead(3).string();
  double worst = 0.0;
  int cases = 0;
  for (double mu : {0.1, 0.4, 1.0})
    for (const Vector3d& offset : {Vector3d(0.003, 0.0, 0.0), Vector3d(-0.002, 0.005, 0.0)})
      for (const Vector3d& spin : {Vector3d(0, 0, 0), Vector3d(100, -50, 300)}) {
        auto text = [](const Vector3d& v) {
          char buffer[96];
          std::snprintf(buffer, sizeof buffer, "[%.17g, %.17g, %.17g]", v.x(), v.y(), v.z());
          return std::string(buffer);
        };
        const PackingCase run = run_packing(
            "{" + kSteel + R"(, "beads": {"file": "one.csv"}, "strikers": [{"target": [0],
            "radius": 0.005, "velocity": [0, 0, -1], "offset": )" +
                text(offset) + R"(, "spin": )" + text(spin) + R"(}], "contact": {"restitution": 0.8,
            "friction": )" +
                std::to_string(mu) + R"(}, "impact": {"integrator": "adaptive",
            "tolerance": 1e-12}, "configuration_check": {"enabled": false}})",
            directory);
        Side bead_expected{.mass = run.model.mass(0), .radius = 0.005};
        Side striker_expected{.mass = run.model.mass(3), .radius = 0.005};
        striker_expected.velocity = -Vector3d::UnitZ();
        striker_expected.spin = spin;
        lone_contact(padded(run.model.contacts[0].normal), mu, 0.8, bead_expected,
                     striker_expected);
        worst = std::max({worst, difference(after(run, 0), bead_expected),
                          difference(after(run, 1), striker_expected)});
        ++cases;
      }
  std::printf("%d strikes in space: worst difference %.3e of V\n", cases, worst);
  EXPECT_LT(worst, 1e-10);
}

TEST(PackingFriction, ABeadListedWithItsVelocityAndSpinBouncesOffARoughFloor) {
  // bead 0 strikes the floor at 40 degrees with back-spin; a striker far away ends the run
  const auto directory = std::filesystem::temp_directory_path() / "mimpact_test_packing_floor";
  std::filesystem::create_directories(directory);
  double worst = 0.0;
  for (double mu : {0.05, 0.3, 1.0})
    for (double spin : {-400.0, 0.0, 150.0}) {
      std::ofstream(directory / "floor.csv")
          << "x,y,radius,vx,vy,wz\n0,0.005,0.005,0.766044443118978,-0.642787609686539," << spin
          << "\n1,0.005,0.005,0,0,0\n";
      const PackingCase run = run_packing(
          "{" + kSteel + R"(, "beads": {"file": "floor.csv"}, "walls": [{"side": "bottom"}],
          "strikers": [{"target": [1], "radius": 0.005, "velocity": [0, -1], "gap": 0.001}],
          "contact": {"restitution": 0.7, "friction": )" +
              std::to_string(mu) + R"(}, "impact": {"integrator": "adaptive",
          "tolerance": 1e-12}, "configuration_check": {"enabled": false}})",
          directory.string());
      Side floor, bead_expected{.mass = run.model.mass(0), .radius = 0.005};
      bead_expected.velocity = Vector3d(0.766044443118978, -0.642787609686539, 0.0);
      bead_expected.spin.z() = spin;
      lone_contact(Vector3d::UnitY(), mu, 0.7, floor, bead_expected);
      worst = std::max(worst, difference(after(run, 0), bead_expected));
    }
  std::printf("a bead on a rough floor: worst difference %.3e of its speed\n", worst);
  EXPECT_LT(worst, 1e-10);
}

// The packing's momentum, angular momentum about the origin (the impact's internal impulses act
// at the contact points along their lines and across them in equal and opposite pairs) and
// energy ledger: kinetic and rotational energy lost = normal work + slip work.
void expect_conserved(const PackingCase& run, const char* what) {
  const packings::PackingModel& model = run.model;
  const granular::ImpactOutcome& impact = run.run.impact;
  const double p = packings::momentum(model, model.velocity).norm();
  const double dp =
      (packings::momentum(model, impact.velocity_after) - packings::momentum(model, model.velocity))
          .norm();
  const double t = impact.impact_time;
  const packings::Vector L_before =
      packings::angular_momentum(model, model.velocity, model.rotation->angular_velocity, t);
  const packings::Vector L_after =
      packings::angular_momentum(model, impact.velocity_after, impact.angular_velocity_after, t);
  const double scale = p * 0.005;  // m V R: the striker's angular momentum about its target
  const granular::EnergyLedger ledger = granular::energy_ledger(model, impact);
  const double energy = ledger.kinetic_before + ledger.rotational_before;
  std::printf("%s: momentum %.2e, angular momentum %.2e, energy %.2e; slip took %.3f %%\n", what,
              dp / p, (L_after - L_before).norm() / scale, ledger.imbalance() / energy,
              100.0 * ledger.slip.sum() / energy);
  EXPECT_LT(dp / p, 1e-12);
  EXPECT_LT((L_after - L_before).norm() / scale, 1e-12);
  EXPECT_LT(std::abs(ledger.imbalance()) / energy, 1e-12);
  EXPECT_GT(ledger.slip.minCoeff(), -1e-15 * energy);
  EXPECT_GT(ledger.slip.sum(), 1e-4 * energy);
  EXPECT_LE(ledger.kinetic_after + ledger.rotational_after, energy);
  // the console tells the same: the slip's work, and an angular momentum kept to 9 digits
  const std::string report = packings::packing_report(model, run.run);
  const std::size_t at = report.find("angular momentum [");
  ASSERT_NE(at, std::string::npos) << report;
  const std::string moments = report.substr(at + 17, report.find(" N m s", at) - at - 17);
  const std::size_t arrow = moments.find(" -> ");
  EXPECT_EQ(moments.substr(0, arrow), moments.substr(arrow + 4)) << report;
  EXPECT_NE(report.find("slip took"), std::string::npos);
}

TEST(PackingFriction, AFrictionalPackingKeepsMomentumAndAngularMomentum) {
  const std::string hexagonal = "{" + kSteel + R"(, "lattice": {"type": "hexagonal", "rows": 6,
      "columns": 6, "radius": 0.005}, "strikers": [{"target": [0, 3], "radius": 0.005,
      "velocity": [0.1, 1], "offset": 0.002, "spin": 200}], "contact": {"restitution": 1,
      "friction": 0.3}, "configuration_check": {"enabled": false}, "impact": )";
  for (const char* impact :
       {R"({"integrator": "adaptive", "tolerance": 1e-9})", R"({"delta_p": 2e-6})"})
    expect_conserved(run_packing(hexagonal + impact + "}"), impact);
  // in space: an FCC packing struck from below, off-centre and spinning
  std::string text = "{" + kSteel + R"(, "lattice": {"type": "fcc", "layers": 3, "rows": 3,
      "columns": 3, "radius": 0.005}, "strikers": [{"target": [0, 1, 1], "radius": 0.005,
      "velocity": [0, 0, 1], "offset": [0.002, -0.001, 0], "spin": [50, 0, -80]}],
      "contact": {"restitution": 0.9, "friction": 0.4}, "configuration_check": {"enabled": false},
      "impact": {"integrator": "adaptive", "tolerance": 1e-9}})";
  expect_conserved(run_packing(text), "FCC 3^3, adaptive");
}

// Each bad input is refused before the run, naming its field, its value and what is allowed.
TEST(PackingFriction, BadOffsetsSpinsAndUnsupportedCombinationsAreRefused) {
  const std::string planar = one_bead(2).string();
  auto refusal = [&](const std::string& striker, const std::string& rest,
                     const std::string& directory) {
    try {
      run_packing("{" + kSteel + R"(, "beads": {"file": "one.csv"}, "strikers": [{"target": [0],
          "radius": 0.005, )" +
                      striker + "}]" + rest + "}",
                  directory);
    } catch (const InvalidInput& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  const std::string rough = R"(, "contact": {"friction": 0.3})";
  EXPECT_NE(refusal(R"("velocity": [1, 0], "offset": 0.01)", rough, planar)
                .find("strikers[0].offset = 0.01 is invalid; allowed: |offset| < 0.01 m"),
            std::string::npos);
  EXPECT_NE(refusal(R"("velocity": [1, 0], "spin": [1, 2, 3])", rough, planar)
                .find("strikers[0].spin = [1, 2, 3] has 3 components; allowed: 1"),
            std::string::npos);
  EXPECT_NE(refusal(R"("velocity": [1, 0], "offset": "far")", rough, planar)
                .find("strikers[0].offset = \"far\" is invalid; allowed: m, a number in the plane"),
            std::string::npos);
  EXPECT_NE(
      refusal(R"("velocity": [0, 0, -1], "offset": [0.001, 0, 0.001])", rough, one_bead(3).string())
          .find("is not perpendicular to its velocity"),
      std::string::npos);
  EXPECT_NE(refusal(R"("velocity": [1, 0])",
                    R"(, "contact": {"friction": 0.3, "restitution": 0.9}, "method": "compliant")",
                    planar)
                .find("contact.restitution = 0.9 is invalid; allowed: 1 with friction in the "
                      "moving geometry"),
            std::string::npos);
  EXPECT_NE(refusal(R"("velocity": [1, 0])", R"(, "contact": {"friction": -0.1})", planar)
                .find("contact.friction = -0.1 is invalid"),
            std::string::npos);
  EXPECT_NE(
      refusal(R"("velocity": [1, 0])",
              rough + R"(, "impact": {"integrator": "asynchronous", "delta_p": 1e-6})", planar)
          .find("friction"),
      std::string::npos);
}

// The frames of a frictional impact take its tangential impulses (the LZB integrators), or the
// spins of the compliant contacts in the frozen configuration: at every frame the bodies keep
// their momentum and angular momentum (the impulses so far are internal, along and across the
// frozen lines of contact), and the last frame is the run's post-impact state.
TEST(PackingFriction, FramesCarryTheTangentialImpulsesAndTheSpins) {
  for (const char* impact :
       {R"("impact": {"integrator": "adaptive", "tolerance": 1e-10})",
        R"("impact": {"delta_p": 2e-6})",
        R"("method": "compliant", "compliant": {"tolerance": 1e-10, "geometry": "frozen"})"}) {
    const PackingCase run = run_packing("{" + kSteel + R"(, "lattice": {"type": "hexagonal",
        "rows": 4, "columns": 4, "radius": 0.005}, "strikers": [{"target": [0, 1],
        "radius": 0.005, "velocity": [0, 1], "offset": 0.003, "spin": -150}],
        "contact": {"restitution": 0.9, "friction": 0.3}, "configuration_check": {"enabled": false},
        "record": {"beads": [1, 16], "interval": 2e-6, "every": 50, "frames": 1}, )" +
                                        std::string(impact) + "}");
    const packings::PackingModel& model = run.model;
    const granular::Frames& frames = run.run.frames;
    ASSERT_GT(frames.time.size(), 5u);
    ASSERT_EQ(frames.angular_velocity.size(), frames.time.size());
    const double t = run.run.impact.impact_time;
    const packings::Vector p0 = packings::momentum(model, model.velocity);
    const packings::Vector L0 =
        packings::angular_momentum(model, model.velocity, model.rotation->angular_velocity, t);
    double drift = 0.0;
    for (std::size_t f = 0; f < frames.time.size(); ++f) {
      const Eigen::Map<const Eigen::VectorXd> v(frames.velocity[f].data(),
                                                Eigen::Index(frames.velocity[f].size()));
      const Eigen::Map<const Eigen::VectorXd> w(frames.angular_velocity[f].data(),
                                                Eigen::Index(frames.angular_velocity[f].size()));
      drift = std::max(
          {drift, (packings::momentum(model, v) - p0).norm() / p0.norm(),
           (packings::angular_momentum(model, v, w, t) - L0).norm() / (p0.norm() * 0.005)});
    }
    const Eigen::Map<const Eigen::VectorXd> last_v(frames.velocity.back().data(),
                                                   Eigen::Index(frames.velocity.back().size()));
    const Eigen::Map<const Eigen::VectorXd> last_w(
        frames.angular_velocity.back().data(), Eigen::Index(frames.angular_velocity.back().size()));
    const double end =
        std::max((last_v - run.run.impact.velocity_after).cwiseAbs().maxCoeff(),
                 0.005 * (last_w - run.run.impact.angular_velocity_after).cwiseAbs().maxCoeff());
    const std::vector<double>& series = run.run.series.velocity.back();  // beads 1 and 16
    const double recorded = std::max(std::abs(series[0] - run.run.impact.velocity_after(2)),
                                     std::abs(series[3] - run.run.impact.velocity_after(33)));
    std::printf("%s: %zu frames, momenta drift %.2e; last frame %.2e, series %.2e from the end\n",
                impact, frames.time.size(), drift, end, recorded);
    EXPECT_LT(drift, 1e-12);
    EXPECT_LT(end, 1e-12);
    EXPECT_LT(recorded, 1e-12);
  }
}

// contact.pairs sets mu per pair of named materials, over contact.friction: a glass bead on a
// felt floor at mu = 0.8, beside steel on glass at 0.2, meet their closed forms.
TEST(PackingFriction, FrictionPerPairOfMaterials) {
  const auto directory = std::filesystem::temp_directory_path() / "mimpact_test_packing_pairs";
  std::filesystem::create_directories(directory);
  std::ofstream(directory / "pair.csv")
      << "x,y,radius,vx,vy,wz\n0,0.005,0.005,0.6,-0.8,0\n0.1,0.05,0.005,0,0,0\n";
  const std::string glass = R"({"name": "glass", "density": 2500, "young": 6e10, "poisson": 0.2})";
  const PackingCase run = run_packing(
      R"({"beads": {"file": "pair.csv", "material": )" + glass +
          R"(}, "walls": [{"side": "bottom", "material": {"name": "felt", "density": 1000,
          "young": 1e9, "poisson": 0.3}}], "strikers": [{"target": [1], "radius": 0.005,
          "velocity": [1, 0], "offset": 0.004, "gap": 0.001, "material": {"name": "steel",
          "density": 7780, "young": 2.03e11, "poisson": 0.3}}], "contact": {"restitution": 0.8,
          "friction": 0.05, "pairs": [{"materials": ["felt", "glass"], "friction": 0.8},
          {"materials": ["glass", "steel"], "friction": 0.2}]}, "impact": {"integrator":
          "adaptive", "tolerance": 1e-12}, "configuration_check": {"enabled": false}})",
      directory.string());
  const packings::PackingModel& model = run.model;
  Side floor, bead{.mass = model.mass(0), .radius = 0.005};
  bead.velocity = Vector3d(0.6, -0.8, 0.0);
  lone_contact(Vector3d::UnitY(), 0.8, 0.8, floor, bead);
  Side target{.mass = model.mass(2), .radius = 0.005},
      striker{.mass = model.mass(4), .radius = 0.005};
  striker.velocity = Vector3d::UnitX();
  const auto striker_contact = std::find_if(model.contacts.begin(), model.contacts.end(),
                                            [](const auto& c) { return c.second == 2; });
  ASSERT_NE(striker_contact, model.contacts.end());
  lone_contact(padded(striker_contact->normal), 0.2, 0.8, target, striker);
  const double worst = std::max({difference(after(run, 0), bead), difference(after(run, 1), target),
                                 difference(after(run, 2), striker)});
  std::printf("friction per pair: worst difference %.3e of V\n", worst);
  EXPECT_LT(worst, 1e-10);
  try {
    run_packing(R"({"beads": {"file": "pair.csv", "material": )" + glass + R"(}, "strikers": [{
        "target": [1], "radius": 0.005, "velocity": [1, 0], "material": )" +
                    glass +
                    R"(}], "contact": {"pairs": [{"materials": ["glass", "rubber"],
        "friction": 1}]}})",
                directory.string());
    ADD_FAILURE() << "an unknown material name was accepted";
  } catch (const InvalidInput& error) {
    EXPECT_NE(std::string(error.what())
                  .find("contact.pairs[0].materials[1] = \"rubber\" names no material of the "
                        "scene; allowed: glass"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace mimpact::testing
