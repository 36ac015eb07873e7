"""A steel ball dropped from 1 m on a steel floor, e = 0.8, written with the kernel from Python.

The same model as examples/bouncing_ball (C++): one body, its height z; one interaction, the
gap g = z - R to the floor, with the LZB law of the Hertz contact; the event-driven integrator
with the LZB impact problem and the acceleration-level LCP, chosen by name. It prints the
bounce times and apex heights against the rigid bounce's geometric series, then the ball at
rest with the floor carrying its weight, the numbers the C++ example prints.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/bouncing_ball.py
"""

import math

import mimpact

STEEL = {"density": 7800.0, "young": 210e9, "poisson": 0.3}
RADIUS, DROP_HEIGHT, GRAVITY, RESTITUTION = 0.01, 1.0, 9.81, 0.8


def bounce(end_time=5.0):
    """Runs the drop; returns the bounces (time, height, rebound speed), the forces at rest
    and the run's summary."""
    mass = mimpact.bead_mass(RADIUS, STEEL)
    ball = mimpact.LagrangianLinearTIDS(
        [DROP_HEIGHT], [0.0], [[mass]], external_force=[-mass * GRAVITY], name="ball")
    law = mimpact.LzbLaw(stiffness=mimpact.hertz_stiffness_wall(RADIUS, STEEL, STEEL),
                         restitution=RESTITUTION)
    system = mimpact.NonSmoothDynamicalSystem()
    system.add(ball)
    system.add(mimpact.Interaction(ball, mimpact.LinearRelation([1.0], -RADIUS), law, "floor"))

    simulation = mimpact.Simulation(system, integrator="event-driven",
                                    impact_options={"relative_delta_p": 1e-3})
    bounces, resting = [], []

    def on_impact(state, impact):
        bounces.append((impact.time, state.system.system(0).position[0], impact.velocity_after[0]))

    def on_step(state, step):
        if not resting and step.contact_forces is not None and step.contact_forces.force.size:
            resting.append((step.contact_forces.time, step.contact_forces.force[0]))

    simulation.add_observer(on_impact=on_impact, on_step=on_step)
    summary = simulation.run(0.0, end_time)
    return mass, bounces, resting, summary


def main():
    mass, bounces, resting, summary = bounce()
    first_speed = math.sqrt(2.0 * GRAVITY * (DROP_HEIGHT - RADIUS))
    expected_time = math.sqrt(2.0 * (DROP_HEIGHT - RADIUS) / GRAVITY)
    print("bounce  time (s)          rigid series (s)   apex (m)          rigid series (m)")
    for k, (time, height, speed) in enumerate(bounces[:12]):
        outgoing = RESTITUTION ** (k + 1) * first_speed
        apex = height + speed * speed / (2.0 * GRAVITY)
        print(f"{k + 1:4d}  {time:.12f}  {expected_time:.12f}  {apex:.12f}  "
              f"{RADIUS + outgoing * outgoing / (2.0 * GRAVITY):.12f}")
        expected_time += 2.0 * outgoing / GRAVITY
    if resting:
        time, force = resting[0]
        print(f"{len(bounces)} impacts; at rest from t = {time:.6f} s with floor force "
              f"{force:.6f} N (m g = {mass * GRAVITY:.6f} N)")
    print(f"{summary.events} events, {summary.smooth_steps} smooth steps, "
          f"{summary.wall_time:.3f} s of computation")


if __name__ == "__main__":
    main()
