// Example a: a ball dropped on the floor, e = 0.8. Its bounces follow the geometric series
// of a rigid bounce (the LZB law of one contact gives u+ = -e u- exactly), then it rests
// with the floor carrying its weight.
#include <gtest/gtest.h>

#include <cmath>

#include "mimpact/models/bouncing_ball.hpp"
#include "mimpact/models/simulation_setup.hpp"

namespace mimpact::models {
namespace {

TEST(BouncingBall, GeometricSeriesThenRestUnderItsWeight) {
  const BouncingBall ball;
  SimulationSetup setup;
  setup.impacts.relative_delta_p = ball.relative_delta_p;
  kernel::Simulation simulation = make_simulation(ball.build(), setup);
  BounceRecord record;
  simulation.add_observer(record);
  simulation.run(0.0, 5.0);

  const double g = ball.gravity, e = ball.restitution;
  const double drop = ball.drop_height - ball.radius;
  const double first_speed = std::sqrt(2.0 * g * drop);
  ASSERT_GE(record.times.size(), 10u);
  double time = std::sqrt(2.0 * drop / g);
  for (int k = 0; k < 10; ++k) {
    const double outgoing = std::pow(e, k + 1) * first_speed;
    const double apex = record.heights[k] + record.speeds[k] * record.speeds[k] / (2.0 * g);
    EXPECT_NEAR(record.times[k], time, 1e-6 * time) << "bounce " << k + 1;
    EXPECT_NEAR(apex - ball.radius, outgoing * outgoing / (2.0 * g),
                1e-6 * outgoing * outgoing / (2.0 * g))
        << "bounce " << k + 1;
    time += 2.0 * outgoing / g;
  }
  // the series accumulates at t1 + 2 e w / (g (1 - e)); the accumulation rule ends it
  // when a flight would last under rest_flight_time (1 us)
  const double accumulation = std::sqrt(2.0 * drop / g) + 2.0 * e * first_speed / (g * (1.0 - e));
  ASSERT_TRUE(record.resting);
  EXPECT_NEAR(record.resting->time, accumulation, 1e-5);
  EXPECT_NEAR(record.resting->force(0), ball.mass() * g, 1e-12 * ball.mass() * g);
  EXPECT_EQ(simulation.system().index_sets().persistent, std::vector<kernel::Index>{0});
  EXPECT_NEAR(simulation.system().system(0).position()(0), ball.radius, 1e-9);
  EXPECT_EQ(simulation.system().system(0).velocity()(0), 0.0);
}

}  // namespace
}  // namespace mimpact::models
