"""A billiard break with spin and friction: a rack of 15 balls struck at its apex by a cue ball
with side spin ("english", about the vertical axis), off-centre, with and without friction
between the balls. The rack is a planar packing listed ball by ball (the cue ball is its
striker); the LZB impact with Coulomb friction (docs/model.md, section 16) gives every ball's
velocity and spin after the break. Friction turns the object balls and throws them off the
frictionless directions ("throw", Alciatore 2004), and takes part of the energy.

Pool balls (Alciatore, "The Illustrated Principles of Pool and Billiards", 2004): 57.15 mm,
0.17 kg, ball-ball restitution 0.93 and friction 0.06. Their modulus (phenolic resin, a few GPa)
sets the impact's duration, not its outcome: LZB's distribution in a rack of equal balls does
not depend on it. The table is not modelled (nothing rolls): these are the velocities just
after the break. The configuration check against the moving geometry is off: the compliant
contacts have no friction yet.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/billiard_break.py [--out DIR]
"""

import argparse
import math
import pathlib

import numpy as np

import mimpact

RADIUS = 0.05715 / 2  # m
MASS = 0.17  # kg
SPEED, SPIN, OFFSET = 8.0, 100.0, 0.002  # m/s, rad/s (about z), m


def rack():
    """The 15 balls, apex at the origin and the rack opening along +x, each row touching."""
    rows = []
    for row in range(5):
        for k in range(row + 1):
            rows.append((row * math.sqrt(3.0) * RADIUS, (2 * k - row) * RADIUS))
    return rows


def scene(directory, friction):
    density = MASS / (4.0 / 3.0 * math.pi * RADIUS**3)
    lines = ["x,y,radius"] + [f"{x:.17g},{y:.17g},{RADIUS:.17g}" for x, y in rack()]
    (directory / "rack.csv").write_text("\n".join(lines) + "\n")
    return {"material": {"density": density, "young": 5e9, "poisson": 0.35},
            "beads": {"file": "rack.csv"},
            "strikers": [{"target": [0], "radius": RADIUS, "velocity": [SPEED, 0.0],
                          "offset": OFFSET, "spin": SPIN, "gap": 0.01}],
            "contact": {"restitution": 0.93, "friction": friction},
            "impact": {"integrator": "adaptive", "tolerance": 1e-10},
            "configuration_check": {"enabled": False}}


def report(name, result):
    summary = result.summary
    energy = summary["energy"]
    before = energy["kinetic_before"] + energy["rotational_before"]
    after = energy["kinetic_after"] + energy["rotational_after"]
    momentum = summary["momentum"]
    moment = summary["angular_momentum"]
    print(f"{name}: energy {before:.4f} J -> {after:.4f} J, slip took "
          f"{energy['slip_total']:.4f} J; momentum change "
          f"{np.linalg.norm(np.subtract(momentum['after'], momentum['before'])):.1e} N s, "
          f"angular momentum change {abs(moment['after'][0] - moment['before'][0]):.1e} N m s")
    spins = result.post_impact_angular_velocities[:, 0]
    print(f"{name}: cue ball {result.post_impact_velocities[-1]} m/s, spin {spins[-1]:.2f} "
          f"rad/s; object balls' spins from {spins[:-1].min():.2f} to {spins[:-1].max():.2f}")


def draw(results, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle
    figure, panels = plt.subplots(1, 2, figsize=(10, 4.6), sharey=True)
    largest = max(abs(r.post_impact_angular_velocities).max() for _, r in results)
    colours = plt.get_cmap("coolwarm")
    for axes, (name, result) in zip(panels, results):
        centres, velocities = result.positions, result.post_impact_velocities
        spins = result.post_impact_angular_velocities[:, 0]
        for ball, (centre, spin) in enumerate(zip(centres, spins)):
            cue = ball == len(centres) - 1  # where it started, dashed
            axes.add_patch(Circle(centre, RADIUS, facecolor=colours(0.5 + spin / (2 * largest)),
                                  edgecolor="black", linewidth=0.6, linestyle="--" if cue else "-"))
        axes.quiver(centres[:, 0], centres[:, 1], velocities[:, 0], velocities[:, 1],
                    angles="xy", scale_units="xy", scale=40.0, width=0.004)
        axes.set_title(name)
        axes.set_aspect("equal")
        axes.set_xlim(-5 * RADIUS, 11 * RADIUS)
        axes.set_ylim(-7 * RADIUS, 7 * RADIUS)
        axes.set_xlabel("x (m)")
    panels[0].set_ylabel("y (m)")
    mappable = plt.cm.ScalarMappable(cmap=colours, norm=plt.Normalize(-largest, largest))
    figure.colorbar(mappable, ax=panels, label="spin after the break (rad/s, about z)")
    figure.suptitle(f"Break at {SPEED:g} m/s with {SPIN:g} rad/s of side spin, {OFFSET * 1e3:g} "
                    "mm off-centre (the cue ball dashed, where it started)\nvelocities after the "
                    "impact (arrows, 1 ball radius = 1.1 m/s)", fontsize=10)
    out.mkdir(parents=True, exist_ok=True)
    figure.savefig(out / "billiard_break.png", dpi=130)
    print(f"figure: {out / 'billiard_break.png'}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="build/python-examples", help="directory of the PNG")
    arguments = parser.parse_args()
    out = pathlib.Path(arguments.out)
    out.mkdir(parents=True, exist_ok=True)
    results = []
    for name, friction in (("frictionless", 0.0), ("friction 0.06", 0.06)):
        result = mimpact.run_packing(scene(out, friction), data_dir=out)
        report(name, result)
        results.append((name, result))
    draw(results, out)


if __name__ == "__main__":
    main()
