"""A column of ten steel beads resting on a steel floor, struck by an eleventh dropped from
5 cm, written with the kernel from Python: the same model and numbers as examples/bead_column
(C++). The beads are LagrangianDS whose weight is a Python callable, so the run also shows the
kernel calling back into Python.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/bead_column.py
"""

import mimpact

STEEL = {"density": 7800.0, "young": 210e9, "poisson": 0.3}
BEADS, RADIUS, GRAVITY, DROP_HEIGHT, RESTITUTION = 10, 0.01, 9.81, 0.05, 0.7


def build():
    """Heights z of the centres, bottom bead first, the striker last; contact 0 is the floor's,
    contact i joins beads i - 1 and i."""
    mass = mimpact.bead_mass(RADIUS, STEEL)
    system = mimpact.NonSmoothDynamicalSystem()
    bodies = []
    for i in range(BEADS + 1):
        height = RADIUS * (2 * i + 1) + (DROP_HEIGHT if i == BEADS else 0.0)
        body = mimpact.LagrangianDS([height], [0.0], [[mass]],
                                    external_force=lambda t: [-mass * GRAVITY],
                                    name="striker" if i == BEADS else f"bead {i}")
        system.add(body)
        bodies.append(body)
    floor = mimpact.LzbLaw(stiffness=mimpact.hertz_stiffness_wall(RADIUS, STEEL, STEEL),
                           restitution=RESTITUTION)
    between = mimpact.LzbLaw(stiffness=mimpact.hertz_stiffness(RADIUS, STEEL, RADIUS, STEEL),
                             restitution=RESTITUTION)
    system.add(mimpact.Interaction(bodies[0], mimpact.LinearRelation([1.0], -RADIUS), floor,
                                   "floor"))
    for i in range(1, BEADS + 1):
        system.add(mimpact.Interaction(bodies[i - 1], bodies[i],
                                       mimpact.LinearRelation([-1.0, 1.0], -2.0 * RADIUS),
                                       between, f"contact {i}"))
    return mass, system


def strike(end_time=1.0):
    """Runs the strike; returns the bead weight, the forces before and after, the first impacts
    and the run's summary."""
    mass, system = build()
    simulation = mimpact.Simulation(system, impact_options={"relative_delta_p": 1e-3})
    forces, impacts = [], []

    def on_step(state, step):
        if step.contact_forces is not None:
            forces.append((step.contact_forces.time, step.contact_forces.force.copy()))

    simulation.add_observer(on_step=on_step, on_impact=lambda state, impact: impacts.append(
        (impact.time, len(impact.interactions), impact.steps, impact.duration)))
    summary = simulation.run(0.0, end_time)
    return mass * GRAVITY, forces[0], forces[-1], impacts, summary


def main():
    weight, first, last, impacts, summary = strike()
    for time, contacts, steps, duration in impacts[:3]:
        print(f"impact at t = {time:.6f} s among {contacts} contacts, {steps} steps, "
              f"lasting {duration:.3g} s")
    for when, (time, force) in (("before the strike", first), ("settled", last)):
        shares = " ".join(f"{f / weight:.6f}" for f in force)
        print(f"{when} (t = {time:.4f} s), contact forces / bead weight: {shares}")
    print(f"{len(impacts)} impacts, {summary.events} events, {summary.smooth_steps} smooth steps, "
          f"{summary.wall_time:.3f} s of computation")


if __name__ == "__main__":
    main()
