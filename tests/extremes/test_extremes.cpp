// Both LZB integrators at the extremes of their parameters: restitution 0 to 1,
// elasticity exponents 1 to 2.5, stiffness and mass ratios of 1e6 and 1e4, delta_p from 1e-3
// to 1e-9 of the natural impulse, striker speeds from 1e-4 to 10 m/s, chains of 2 to 100 000
// beads, strikes at both ends, a grazing contact. Every run must end, stay finite, conserve
// momentum to round-off, never gain energy beyond O(delta_p) (lose it for e < 1), and take
// at most the steps its impulses need:
//   steps <= sum_j P_j / delta_p + 2 m + 1,
// since every step but the last of a primary's phase moves the primary by delta_p, and each
// of the m contacts ends a phase as primary at most twice (compression, then expansion)
// per compression it goes through; the bound is checked where each contact is compressed once.
// The adaptive integrator runs over the same grid and tolerances 1e-3 to 1e-12: it must end,
// stay finite, conserve momentum to round-off and never gain energy beyond its tolerance; a
// tolerance double precision cannot meet is refused.
#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "mimpact/common/error.hpp"
#include "mimpact/numerics/lzb_adaptive_integrator.hpp"
#include "mimpact/numerics/lzb_impulse_integrator.hpp"

namespace mimpact::numerics {
namespace {

using Eigen::VectorXd;

constexpr double kBeadMass = 0.0326;  // kg: C1's 10 mm steel bead
constexpr double kStiffness =
    1e10;  // N / m^eta; uniform K leaves LZB's velocities independent of it

// Bodies on a line, contact j between bodies j and j + 1 (u_j = v_(j+1) - v_j, < 0 approaching).
struct Line {
  VectorXd mass, velocity;
  std::vector<ContactLaw> laws;

  Eigen::Index contacts() const { return mass.size() - 1; }
  Eigen::SparseMatrix<double> H() const {
    std::vector<Eigen::Triplet<double>> entries;
    for (Eigen::Index j = 0; j < contacts(); ++j) {
      entries.emplace_back(j, j, 1.0 / mass(j) + 1.0 / mass(j + 1));
      if (j + 1 < contacts()) {
        entries.emplace_back(j, j + 1, -1.0 / mass(j + 1));
        entries.emplace_back(j + 1, j, -1.0 / mass(j + 1));
      }
    }
    Eigen::SparseMatrix<double> h(contacts(), contacts());
    h.setFromTriplets(entries.begin(), entries.end());
    return h;
  }
  VectorXd u_minus() const { return velocity.tail(contacts()) - velocity.head(contacts()); }
  // v + M^-1 W P: contact j pushes body j back and body j + 1 on
  VectorXd velocity_after(const VectorXd& impulse) const {
    VectorXd v = velocity;
    for (Eigen::Index j = 0; j < contacts(); ++j) {
      v(j) -= impulse(j) / mass(j);
      v(j + 1) += impulse(j) / mass(j + 1);
    }
    return v;
  }
  double kinetic_energy(const VectorXd& v) const { return 0.5 * mass.dot(v.cwiseAbs2()); }
  double momentum(const VectorXd& v) const { return mass.dot(v); }
  double momentum_scale() const { return mass.dot(velocity.cwiseAbs()); }
  // m V of the lighter body at the first approaching contact: what delta_p is a share of
  double natural_impulse() const {
    const VectorXd u = u_minus();
    for (Eigen::Index j = 0; j < contacts(); ++j)
      if (u(j) < 0.0) return std::min(mass(j), mass(j + 1)) * -u(j);
    return 0.0;
  }
};

ContactLaw law(double exponent = 1.5, double restitution = 1.0,
               ComplianceModel model = ComplianceModel::bi_stiffness) {
  return {
      .stiffness = kStiffness, .exponent = exponent, .restitution = restitution, .model = model};
}

// A striker of `striker_mass` at `speed` against `beads` beads at rest, all touching.
Line struck_chain(int beads, double speed, const ContactLaw& contact,
                  double striker_mass = kBeadMass, double bead_mass = kBeadMass) {
  Line line;
  line.mass = VectorXd::Constant(beads + 1, bead_mass);
  line.mass(0) = striker_mass;
  line.velocity = VectorXd::Zero(beads + 1);
  line.velocity(0) = speed;
  line.laws.assign(std::size_t(beads), contact);
  return line;
}

// Checks the whole energy along the impact: kinetic (from the impulses) plus stored.
class EnergyWatch : public ImpactObserver {
 public:
  explicit EnergyWatch(const Line& line) : line_(line), impulse_(line.contacts()) {}
  void observe(const ImpactSample& sample) override {
    double stored = 0.0;
    for (std::size_t k = 0; k < sample.contacts.size(); ++k) {
      impulse_(sample.contacts[k]) = sample.impulse[k];
      stored += sample.energy[k];
    }
    largest = std::max(largest, line_.kinetic_energy(line_.velocity_after(impulse_)) + stored);
  }
  double largest = 0.0;

 private:
  const Line& line_;
  VectorXd impulse_;
};

struct Outcome {
  LzbResult result;
  VectorXd velocity;  // of the bodies, after
};

// How an impact is integrated: impulse steps of delta_p = share x natural impulse, or the
// adaptive integrator at `tolerance` when it is > 0. Either bounds the relative energy gain.
struct Integration {
  double share = 0.0;
  double tolerance = 0.0;
  bool adaptive() const { return tolerance > 0.0; }
  // The adaptive tolerance bounds each step's error, a hundredth of it, so that the steps' errors
  // add up to less than the tolerance (the largest measured: 0.93 times it, a lone elastic
  // contact at 1e-12).
  double energy_allowance() const { return adaptive() ? tolerance : share; }
};

Integration adaptive(double tolerance) { return {.tolerance = tolerance}; }

LzbResult integrate(const Line& line, const Integration& how, ImpactObserver* observer,
                    double sample_interval) {
  if (how.adaptive()) {
    LzbAdaptiveIntegrator integrator(
        {.tolerance = how.tolerance, .sample_interval = observer ? sample_interval : 0.0});
    return integrator.integrate(line.H(), line.u_minus(), line.laws, observer);
  }
  LzbOptions options;
  options.delta_p = how.share * line.natural_impulse();
  options.sample_every = observer ? 1 : 0;
  return LzbImpulseIntegrator(options).integrate(line.H(), line.u_minus(), line.laws, observer);
}

// Runs the impact and asserts what every extreme must keep. `watch_energy` samples the whole
// energy along the impact (small lines only: every step, or 400 times for the adaptive
// integrator); `one_compression` checks the impulse steps' bound (each contact compressed once).
Outcome expect_sound(const Line& line, const Integration& how, const std::string& what,
                     bool watch_energy = true, bool one_compression = false) {
  EnergyWatch watch(line);
  Outcome out;
  // the adaptive integrator samples in time: over the duration a first run finds
  const double duration =
      watch_energy && how.adaptive() ? integrate(line, how, nullptr, 0.0).duration : 0.0;
  out.result = integrate(line, how, watch_energy ? &watch : nullptr, duration / 400.0);
  const LzbResult& r = out.result;
  EXPECT_EQ(r.status, LzbStatus::terminated) << what << ": " << r.message;
  EXPECT_TRUE(r.impulse.allFinite() && r.velocity.allFinite() && r.max_force.allFinite() &&
              r.time_of_max_force.allFinite() && std::isfinite(r.duration))
      << what;
  EXPECT_TRUE((r.impulse.array() >= 0.0).all()) << what;
  out.velocity = line.velocity_after(r.impulse);
  EXPECT_NEAR(line.momentum(out.velocity), line.momentum(line.velocity),
              1e-12 * line.momentum_scale())
      << what;

  const double before = line.kinetic_energy(line.velocity),
               after = line.kinetic_energy(out.velocity);
  const bool elastic = std::all_of(line.laws.begin(), line.laws.end(),
                                   [](const ContactLaw& l) { return l.restitution == 1.0; });
  // the relative energy gain is at most the step's share of the natural impulse, O(delta_p),
  // or the adaptive integrator's tolerance
  const double allowance = how.energy_allowance();
  EXPECT_LE(after, before * (1.0 + allowance)) << what;
  if (watch_energy) {
    EXPECT_LE(watch.largest, before * (1.0 + allowance)) << what;
  }
  if (!elastic) {
    EXPECT_LT(after, before) << what;
  }
  if (one_compression && !how.adaptive()) {
    const double delta_p = how.share * line.natural_impulse();
    const double bound = r.impulse.sum() / delta_p + 2.0 * double(line.contacts()) + 1.0;
    EXPECT_LE(double(r.steps), bound) << what;
  }
  std::printf("%-52s %10lld steps, energy %+.3e, momentum %+.1e\n", what.c_str(),
              (long long)r.steps, after / before - 1.0,
              (line.momentum(out.velocity) - line.momentum(line.velocity)) / line.momentum_scale());
  return out;
}

// The impulse steps at delta_p = share x natural impulse.
Outcome expect_sound(const Line& line, double share, const std::string& what,
                     bool watch_energy = true, bool one_compression = false) {
  return expect_sound(line, Integration{.share = share}, what, watch_energy, one_compression);
}

std::string name(const char* what, double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%s %g", what, value);
  return text;
}

// e from perfectly plastic to elastic, both compliance models, three elasticity exponents.
TEST(Extremes, RestitutionAndExponent) {
  for (double exponent : {1.0, 1.5, 2.5})
    for (double e : {0.0, 1e-3, 0.5, 1.0})
      for (ComplianceModel model :
           {ComplianceModel::bi_stiffness, ComplianceModel::mono_stiffness}) {
        const std::string what = name("eta", exponent) + name(", e", e) +
                                 (model == ComplianceModel::mono_stiffness ? ", mono" : ", bi");
        const Outcome out =
            expect_sound(struck_chain(20, 1.0, law(exponent, e, model)), 1e-4, what);
        if (e == 0.0) {
          // nothing comes back: the striker and the first bead leave together or apart, never
          // rebound
          EXPECT_GE(out.velocity(0), -1e-12) << what;
        }
      }
}

// A restitution below 2^-27 gives back less than half an ulp of the compression work: the
// integrators release it at once, as e = 0, to the last bit (e = 1e-100 ran past a minute,
// 1e-300 overflowed 1/e^2; issue 22).
TEST(Extremes, NegligibleRestitutionIsZero) {
  for (const Integration& how : {Integration{.share = 1e-4}, adaptive(1e-8)}) {
    const Outcome zero = expect_sound(struck_chain(20, 1.0, law(1.5, 0.0)), how, "e = 0");
    for (double e : {7e-9, 1e-100, 1e-300, 5e-324}) {
      const Outcome tiny = expect_sound(struck_chain(20, 1.0, law(1.5, e)), how, name("e", e));
      EXPECT_EQ(tiny.velocity, zero.velocity) << e;
      EXPECT_EQ(tiny.result.steps, zero.result.steps) << e;
    }
  }
  // just above, the energy given back is resolved: the striker rebounds by e times its speed
  const Line pair = struck_chain(1, 1.0, law(1.5, 1e-8));
  EXPECT_NEAR(expect_sound(pair, 1e-3, "two bodies, e = 1e-8", true, true).result.velocity(0), 1e-8,
              1e-12);
}

// Two bodies: the post-impact relative velocity is -e u- exactly (a lone contact is exact at
// any delta_p), down to e = 1e-3.
TEST(Extremes, TwoBodiesRestoreTheirRestitution) {
  for (double e : {0.0, 1e-3, 0.5, 1.0}) {
    const Line line = struck_chain(1, 1.0, law(1.5, e));
    const Outcome out = expect_sound(line, 1e-3, name("two bodies, e", e), true, true);
    EXPECT_NEAR(out.result.velocity(0), e * 1.0, 1e-12) << e;
  }
}

// Neighbouring contacts 1e6 times stiffer than each other.
TEST(Extremes, StiffnessRatio1e6) {
  for (double e : {1.0, 0.5}) {
    Line line = struck_chain(20, 1.0, law(1.5, e));
    for (std::size_t j = 1; j < line.laws.size(); j += 2) line.laws[j].stiffness *= 1e6;
    const Outcome out = expect_sound(line, 1e-4, name("stiffness ratio 1e6, e", e));
    EXPECT_GT(out.velocity(20), 0.0);  // the wave gets through
  }
}

// A striker 1e4 times heavier than the beads, and 1e4 times lighter.
TEST(Extremes, MassRatio1e4BothWays) {
  for (double e : {1.0, 0.5}) {
    const Outcome heavy = expect_sound(struck_chain(20, 1.0, law(1.5, e), 1e4 * kBeadMass), 1e-4,
                                       name("striker 1e4 times heavier, e", e));
    EXPECT_GT(heavy.velocity(0), 0.99);  // it barely slows
    const Outcome light = expect_sound(struck_chain(20, 1.0, law(1.5, e), 1e-4 * kBeadMass), 1e-4,
                                       name("striker 1e4 times lighter, e", e), true, true);
    // it bounces off a wall-like chain: back at about e times its speed
    EXPECT_NEAR(light.velocity(0), -e, 0.02 * e) << e;
  }
}

// delta_p from 1e-3 to 1e-9 of m V: two bodies over the whole range, a 20-bead chain to 1e-6.
TEST(Extremes, DeltaPFrom1e3To1e9OfTheNaturalImpulse) {
  for (double share : {1e-3, 1e-5, 1e-7, 1e-9}) {
    const Line line = struck_chain(1, 1.0, law(1.5, 1.0));
    const Outcome out =
        expect_sound(line, share, name("two bodies, delta_p / m V", share), false, true);
    // exact but for round-off, which u and E gather over the steps (1e9 of them at 1e-9)
    const double round_off =
        10.0 * double(out.result.steps) * std::numeric_limits<double>::epsilon();
    EXPECT_NEAR(out.result.velocity(0), 1.0, std::max(1e-12, round_off)) << share;
  }
  for (double share : {1e-3, 1e-4, 1e-5, 1e-6})
    expect_sound(struck_chain(20, 1.0, law(1.5, 0.9)), share,
                 name("20 beads e = 0.9, delta_p / m V", share), share >= 1e-4);
}

// Speeds from 1e-4 to 10 m/s: Hertz contacts have no scale of their own, so with delta_p in
// proportion to m V every run is the same impact and v+ / V agrees to round-off.
TEST(Extremes, StrikerSpeedFrom1e4To10MetresPerSecond) {
  VectorXd reference;
  for (double speed : {1e-4, 1e-2, 1.0, 10.0}) {
    const Outcome out =
        expect_sound(struck_chain(20, speed, law(1.5, 0.8)), 1e-4, name("speed (m/s)", speed));
    const VectorXd scaled = out.velocity / speed;
    if (reference.size() == 0) reference = scaled;
    const double difference = (scaled - reference).cwiseAbs().maxCoeff();
    std::printf("  largest |v+ / V - v+ / V at 1e-4 m/s| = %.1e\n", difference);
    EXPECT_LT(difference, 1e-9) << speed;
  }
}

// 2 to 100 000 beads: the work of a step follows the wave, so it stays bounded.
TEST(Extremes, ChainsFrom2To100000Beads) {
  for (int beads : {2, 10, 1000, 100000}) {
    const Outcome out = expect_sound(struck_chain(beads, 1.0, law(1.5, 1.0)),
                                     beads > 1000 ? 3e-3 : 1e-3, name("beads", beads), beads <= 10);
    const double contacts_per_step = double(out.result.contact_steps) / double(out.result.steps);
    std::printf("  %.2f contacts per step\n", contacts_per_step);
    EXPECT_LT(contacts_per_step, 12.0) << beads;
    EXPECT_GT(out.velocity(beads), 0.9) << beads;  // the solitary wave leaves the last bead
  }
}

// Strikers at both ends at once, elastic and plastic: the outcome mirrors itself, up to the
// order in which a step visits the contacts, an O(delta_p) effect.
TEST(Extremes, StrikesAtBothEnds) {
  for (double e : {1.0, 0.0}) {
    Line line = struck_chain(20, 1.0, law(1.5, e));
    const Eigen::Index last = line.mass.size() - 1;
    line.velocity(last) = -1.0;
    const double share = 1e-4;
    const Outcome out = expect_sound(line, share, name("both ends, e", e));
    const double asymmetry = (out.velocity + out.velocity.reverse()).cwiseAbs().maxCoeff();
    std::printf("  largest |v_i + v_(n-i)| = %.2e m/s\n", asymmetry);
    EXPECT_LE(asymmetry, share * 1.0) << e;
  }
}

// A grazing contact, approaching at 1e-12 m/s. With delta_p set for 1 m/s impacts the impact
// cannot resolve it: it is left untouched (u+ = u-, no impulse), below the velocity resolution
// the result reports, and the event-driven scheme holds it as a persistent contact. With
// delta_p in proportion to its own m V the lone contact comes out exact. In a chain, a
// grazing contact at the far end neither blocks the impact nor changes the wave.
TEST(Extremes, GrazingContact) {
  const Line two = struck_chain(1, 1e-12, law(1.5, 1.0));
  LzbOptions options;
  options.delta_p = 1e-4 * kBeadMass;  // 1e8 times the grazing impulse
  const LzbResult coarse =
      LzbImpulseIntegrator(options).integrate(two.H(), two.u_minus(), two.laws);
  EXPECT_EQ(coarse.status, LzbStatus::terminated);
  EXPECT_EQ(coarse.steps, 0);
  EXPECT_EQ(coarse.velocity(0), -1e-12);
  EXPECT_LT(1e-12, options.velocity_tolerance(two.H().coeff(0, 0)));
  const Outcome fine = expect_sound(two, 1e-3, "two bodies grazing at 1e-12 m/s", true, true);
  EXPECT_NEAR(fine.result.velocity(0), 1e-12, 1e-24);

  Line chain = struck_chain(20, 1.0, law(1.5, 1.0));
  Line grazed = chain;
  grazed.velocity(20) = -1e-12;  // the last bead creeps back towards the chain
  const Outcome plain = expect_sound(chain, 1e-4, "chain"),
                touched = expect_sound(grazed, 1e-4, "chain, last contact grazing");
  EXPECT_LT((plain.velocity - touched.velocity).cwiseAbs().maxCoeff(), 1e-9);
}

// The adaptive integrator over the grid above: e from 0 to 1, eta 1 to 2.5, both models.
TEST(ExtremesAdaptive, RestitutionAndExponent) {
  for (double exponent : {1.0, 1.5, 2.5})
    for (double e : {0.0, 1e-3, 0.5, 1.0})
      for (ComplianceModel model :
           {ComplianceModel::bi_stiffness, ComplianceModel::mono_stiffness}) {
        const std::string what = name("adaptive, eta", exponent) + name(", e", e) +
                                 (model == ComplianceModel::mono_stiffness ? ", mono" : ", bi");
        const Outcome out =
            expect_sound(struck_chain(20, 1.0, law(exponent, e, model)), adaptive(1e-8), what);
        if (e == 0.0) {
          EXPECT_GE(out.velocity(0), -1e-12) << what;
        }
      }
}

// A lone contact: u+ = -e u- to the tolerance (x V = 1 m/s; the tolerance bounds each step's
// error, their sum comes to at most 0.93 times it) at every tolerance from 1e-3 to 1e-12,
// and at 1e-13, the smallest double precision meets; below, the tolerance is refused, not
// looped on.
TEST(ExtremesAdaptive, TolerancesFrom1e3To1e12) {
  for (double tolerance : {1e-3, 1e-6, 1e-9, 1e-12, 1e-13})
    for (double e : {0.0, 0.5, 1.0}) {
      const Outcome out =
          expect_sound(struck_chain(1, 1.0, law(1.5, e)), adaptive(tolerance),
                       name("adaptive, two bodies, tolerance", tolerance) + name(", e", e));
      EXPECT_NEAR(out.result.velocity(0), e, tolerance) << tolerance;
    }
  for (double tolerance : {1e-3, 1e-6, 1e-9, 1e-12})
    expect_sound(struck_chain(20, 1.0, law(1.5, 0.9)), adaptive(tolerance),
                 name("adaptive, 20 beads e = 0.9, tolerance", tolerance), tolerance >= 1e-9);
  for (double tolerance : {1e-14, 0.0, -1.0, std::numeric_limits<double>::quiet_NaN()}) {
    try {
      LzbAdaptiveIntegrator integrator({.tolerance = tolerance});
      ADD_FAILURE() << "tolerance " << tolerance << " accepted";
    } catch (const InvalidInput& error) {
      EXPECT_NE(std::string(error.what()).find("double precision cannot meet it"),
                std::string::npos)
          << error.what();
    }
  }
}

TEST(ExtremesAdaptive, StiffnessAndMassRatios) {
  for (double e : {1.0, 0.5}) {
    Line line = struck_chain(20, 1.0, law(1.5, e));
    for (std::size_t j = 1; j < line.laws.size(); j += 2) line.laws[j].stiffness *= 1e6;
    EXPECT_GT(expect_sound(line, adaptive(1e-8), name("adaptive, stiffness ratio 1e6, e", e))
                  .velocity(20),
              0.0);
    const Outcome heavy =
        expect_sound(struck_chain(20, 1.0, law(1.5, e), 1e4 * kBeadMass), adaptive(1e-8),
                     name("adaptive, striker 1e4 times heavier, e", e));
    EXPECT_GT(heavy.velocity(0), 0.99);
    const Outcome light =
        expect_sound(struck_chain(20, 1.0, law(1.5, e), 1e-4 * kBeadMass), adaptive(1e-8),
                     name("adaptive, striker 1e4 times lighter, e", e));
    EXPECT_NEAR(light.velocity(0), -e, 0.02 * e) << e;
  }
}

// Hertz contacts have no scale of their own, and the tolerance is relative to the fastest
// approach: every speed is the same impact, v+ / V agreeing to round-off.
TEST(ExtremesAdaptive, StrikerSpeedFrom1e4To10MetresPerSecond) {
  VectorXd reference;
  for (double speed : {1e-4, 1e-2, 1.0, 10.0}) {
    const Outcome out = expect_sound(struck_chain(20, speed, law(1.5, 0.8)), adaptive(1e-8),
                                     name("adaptive, speed (m/s)", speed));
    const VectorXd scaled = out.velocity / speed;
    if (reference.size() == 0) reference = scaled;
    EXPECT_LT((scaled - reference).cwiseAbs().maxCoeff(), 1e-9) << speed;
  }
}

TEST(ExtremesAdaptive, ChainsFrom2To100000Beads) {
  for (int beads : {2, 10, 1000, 100000}) {
    const Outcome out = expect_sound(struck_chain(beads, 1.0, law(1.5, 1.0)), adaptive(1e-6),
                                     name("adaptive, beads", beads), beads <= 10);
    const double contacts_per_step = double(out.result.contact_steps) / double(out.result.steps);
    std::printf("  %.2f contacts per step\n", contacts_per_step);
    EXPECT_LT(contacts_per_step, 12.0) << beads;
    EXPECT_GT(out.velocity(beads), 0.9) << beads;
  }
}

// Both ends struck at once: the adaptive integrator treats all contacts at once, so the
// outcome mirrors itself to the tolerance.
TEST(ExtremesAdaptive, StrikesAtBothEnds) {
  for (double e : {1.0, 0.0}) {
    Line line = struck_chain(20, 1.0, law(1.5, e));
    line.velocity(line.mass.size() - 1) = -1.0;
    const Outcome out = expect_sound(line, adaptive(1e-8), name("adaptive, both ends, e", e));
    EXPECT_LE((out.velocity + out.velocity.reverse()).cwiseAbs().maxCoeff(), 1e-8) << e;
  }
}

// A contact grazing at 1e-12 m/s is resolved to the tolerance of its own approach (unlike the
// impulse steps at a delta_p set for 1 m/s, it needs no delta_p of its own), and a grazing
// contact at the far end of a struck chain changes nothing.
TEST(ExtremesAdaptive, GrazingContact) {
  const Outcome lone = expect_sound(struck_chain(1, 1e-12, law(1.5, 1.0)), adaptive(1e-10),
                                    "adaptive, two bodies grazing at 1e-12 m/s");
  EXPECT_NEAR(lone.result.velocity(0), 1e-12, 1e-10 * 1e-12);
  Line chain = struck_chain(20, 1.0, law(1.5, 1.0));
  Line grazed = chain;
  grazed.velocity(20) = -1e-12;
  const Outcome plain = expect_sound(chain, adaptive(1e-10), "adaptive, chain"),
                touched = expect_sound(grazed, adaptive(1e-10), "adaptive, chain, last grazing");
  EXPECT_LT((plain.velocity - touched.velocity).cwiseAbs().maxCoeff(), 1e-9);
}

}  // namespace
}  // namespace mimpact::numerics
