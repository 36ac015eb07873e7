// Nesterenko's theory as Coste, Falcon & Fauve (1997) write it, against the numbers they publish.
#include "mimpact/analysis/nesterenko.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace mimpact::analysis {
namespace {

// the stainless steel beads of Coste, Falcon & Fauve
const BeadChain kCoste{0.004, 2.26e11, 0.3, 7650.0};

TEST(Nesterenko, MaterialConstantsOfThePaper) {
  EXPECT_NEAR(kCoste.theta(), 3.02e-12, 0.005e-12);
  EXPECT_NEAR(kCoste.C(), 4.55e3, 0.01e3);
  EXPECT_NEAR(kCoste.mass(), 2.05e-3, 0.01e-3);
}

// The speeds printed with the pulses of figures 13-15 (F_0 = 0) are eq. 24 at the sensor.
TEST(Nesterenko, SpeedsOfThePulsesWithoutStaticForce) {
  const double pairs[][2] = {{36.7, 629},  {48.5, 659},   {61.4, 685},   {86.4, 725},
                             {168.5, 811}, {216.2, 845},  {269.7, 877},  {356.4, 919},
                             {473.1, 963}, {594.0, 1000}, {646.1, 1014}, {704.6, 1029}};
  for (const auto& [force, speed] : pairs)
    EXPECT_NEAR(solitary_wave_speed(kCoste, force, ForceSite::sensor), speed, 0.004 * speed)
        << force << " N";
  // the sensor's plane-sphere contact: the same wave shows half the bead-bead force there
  EXPECT_NEAR(solitary_wave_speed(kCoste, 100.0, ForceSite::sensor),
              solitary_wave_speed(kCoste, 200.0, ForceSite::between_beads), 1e-9);
}

// With a static force, eq. 21 gives the strain ratios of the captions of figures 6-7
// (3.7 ... 17.0 at F_0 = 29.7 N) and the measured speeds follow eq. 22 with the slope
// k = 0.84 the paper fits instead of sqrt(2/3).
TEST(Nesterenko, StrainRatiosAndTheMeasuredSlopeWithStaticForce) {
  EXPECT_NEAR(precompressed_solitary_wave(kCoste, 100.0, 29.7, ForceSite::sensor).strain_ratio, 3.7,
              0.06);
  EXPECT_NEAR(precompressed_solitary_wave(kCoste, 1060.0, 29.7, ForceSite::sensor).strain_ratio,
              17.0, 0.2);
  const double measured[][3] = {{29.7, 100, 895},  {29.7, 138, 921},   {29.7, 209, 960},
                                {29.7, 290, 994},  {29.7, 503, 1060},  {29.7, 608, 1086},
                                {29.7, 705, 1106}, {29.7, 1060, 1168}, {167, 274, 1131},
                                {167, 474, 1178},  {167, 842, 1239},   {167, 1005, 1260}};
  double sum = 0.0;
  for (const auto& [static_force, force, speed] : measured) {
    const PrecompressedWave wave =
        precompressed_solitary_wave(kCoste, force, static_force, ForceSite::sensor);
    EXPECT_GT(wave.speed, wave.sound_speed);  // supersonic
    sum += speed / (wave.sound_speed * std::pow(wave.y_infinity, -0.2));
  }
  EXPECT_NEAR(sum / 12.0, 0.84, 0.01);
}

TEST(Nesterenko, StaticForceTendsToTheFreeChain) {
  for (ForceSite site : {ForceSite::sensor, ForceSite::between_beads}) {
    const double free = solitary_wave_speed(kCoste, 300.0, site);
    const double loaded = precompressed_solitary_wave(kCoste, 300.0, 1e-6, site).speed;
    EXPECT_NEAR(loaded, free, 1e-3 * free);
    // a large static force makes the wave a sound wave: V -> c_s
    const PrecompressedWave weak = precompressed_solitary_wave(kCoste, 1.0, 500.0, site);
    EXPECT_NEAR(weak.speed, weak.sound_speed, 0.01 * weak.sound_speed);
  }
}

// Eq. 23 with a vanishing static force is the cos^6 of eq. 28.
TEST(Nesterenko, ShapeTendsToCos6) {
  const double force = 200.0;
  const double speed = solitary_wave_speed(kCoste, force, ForceSite::sensor);
  const double width = solitary_wave_width(kCoste, speed);
  const auto pulse = precompressed_pulse(kCoste, force, 1e-5, ForceSite::sensor, 400);
  ASSERT_GT(pulse.size(), 50u);
  EXPECT_NEAR(pulse.front().second, force, 1e-3 * force);
  for (const auto& [t, f] : pulse) {
    const double phase = t / width;
    const double expected = phase < M_PI / 2 ? force * std::pow(std::cos(phase), 6) : 0.0;
    EXPECT_NEAR(f, expected, 0.01 * force) << "t = " << t;
  }
}

}  // namespace
}  // namespace mimpact::analysis
