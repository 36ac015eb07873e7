// A steel ball dropped from 1 m on a steel floor, e = 0.8: the bounce times and apex
// heights against the geometric series of a rigid bounce, then the ball at rest with the
// floor carrying its weight.
#include <cmath>
#include <cstdio>
#include <vector>

#include "mimpact/models/bouncing_ball.hpp"
#include "mimpact/models/simulation_setup.hpp"

using namespace mimpact;

int main(int argc, char* argv[]) try {
  const models::BouncingBall ball;
  models::SimulationSetup setup;
  plugins::LzbImpactOptions defaults;
  defaults.relative_delta_p = ball.relative_delta_p;
  setup.impacts = models::impact_options_from_command_line(argc, argv, defaults);
  kernel::Simulation simulation = models::make_simulation(ball.build(), setup);
  models::BounceRecord bounces;
  simulation.add_observer(bounces);
  const kernel::RunSummary summary = simulation.run(0.0, 5.0);

  const double g = ball.gravity, e = ball.restitution;
  const double first_speed = std::sqrt(2.0 * g * (ball.drop_height - ball.radius));
  double expected_time = std::sqrt(2.0 * (ball.drop_height - ball.radius) / g);
  std::printf("bounce  time (s)          rigid series (s)   apex (m)          rigid series (m)\n");
  for (std::size_t k = 0; k < bounces.times.size() && k < 12; ++k) {
    const double outgoing = std::pow(e, double(k + 1)) * first_speed;
    const double apex = bounces.heights[k] + bounces.speeds[k] * bounces.speeds[k] / (2.0 * g);
    std::printf("%4zu  %.12f  %.12f  %.12f  %.12f\n", k + 1, bounces.times[k], expected_time, apex,
                ball.radius + outgoing * outgoing / (2.0 * g));
    expected_time += 2.0 * outgoing / g;
  }
  if (bounces.resting)
    std::printf("%zu impacts; at rest from t = %.6f s with floor force %.6f N (m g = %.6f N)\n",
                bounces.times.size(), bounces.resting->time, bounces.resting->force(0),
                ball.mass() * g);
  else
    std::printf("%zu impacts; not at rest by the end of the run\n", bounces.times.size());
  std::printf("%lld events, %lld smooth steps, %.3f s of computation\n", (long long)summary.events,
              (long long)summary.smooth_steps, summary.wall_time);
} catch (const std::exception& error) {
  std::fprintf(stderr, "%s\n", error.what());
  return 2;
}
