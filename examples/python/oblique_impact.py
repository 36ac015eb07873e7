"""The oblique impact of an elastic sphere on a flat (Maw, Barber & Fawcett, Wear 38, 1976): a
steel sphere strikes a wall at incidence 0 to 89 degrees without spin, through the compliant
contact with Hertz's normal force and Mindlin's tangential spring under Coulomb's cap
(docs/friction.md, section 3), and leaves with its contact point sliding forward, stopped, or
turned back by the spring's rebound. In Maw, Barber & Fawcett's variables, the contact point's
tangential velocity over the incident normal speed times 2 (1 - nu) / (mu (2 - nu)), psi_1 before
and psi_2 after with their sign (psi_2 > 0: the contact point's tangential velocity reversed),
psi_2 against psi_1 is one curve for every material and mu: the figure draws it with LAMMPS's
runs of the same sphere (tests/data/lammps/sphere_on_wall_mindlin.csv), the rigid tangential
response (Stronge 2000: rolling, psi_2 = 0, until the slip outlasts the impact) and gross slip,
psi_2 = 7 lambda (1 + e)/2 - psi_1 for a solid sphere, lambda = 2 (1 - nu)/(2 - nu).

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/oblique_impact.py [--out DIR]
"""

import argparse
import math
import pathlib

import numpy as np

import mimpact

RADIUS, DENSITY, YOUNG, POISSON, FRICTION = 0.005, 7780.0, 203e9, 0.3, 0.3
MASS = 4.0 / 3.0 * math.pi * RADIUS**3 * DENSITY
INERTIA = 0.4 * MASS * RADIUS**2
# a wall of the sphere's material, as LAMMPS's pair style has it: F = kn sqrt(r delta) delta,
# k_t = kt sqrt(r delta); so K = kn sqrt(r) and lambda = kt / (1.5 kn) = 2 (1 - nu)/(2 - nu)
KN = 4.0 / 3.0 * YOUNG / (2.0 * (1.0 - POISSON**2))
KT = 8.0 * YOUNG / (4.0 * (2.0 - POISSON) * (1.0 + POISSON))
LAMBDA = KT / (1.5 * KN)
LAMMPS = pathlib.Path(__file__).resolve().parents[2] / "tests/data/lammps/sphere_on_wall_mindlin.csv"


def strike(degrees, ratio=LAMBDA):
    """The sphere (x, z, angle) touching the wall at t = 0, struck at 1 m/s: its velocity and
    spin once the contact has opened. The contact point slips at v_x + r w."""
    theta = math.radians(degrees)
    velocity = [math.sin(theta), -math.cos(theta), 0.0]
    sphere = mimpact.LagrangianLinearTIDS([0.0, RADIUS, 0.0], velocity,
                                          np.diag([MASS, MASS, INERTIA]).tolist(), name="sphere")
    law = mimpact.LzbLaw(stiffness=KN * math.sqrt(RADIUS), friction=FRICTION,
                         tangential_stiffness_ratio=ratio)
    wall = mimpact.LinearRelation([0.0, 1.0, 0.0], -RADIUS, tangents=[[1.0, 0.0, RADIUS]])
    system = mimpact.NonSmoothDynamicalSystem()
    system.add(sphere)
    system.add(mimpact.Interaction(sphere, wall, law, "wall"))
    simulation = mimpact.Simulation(system, integrator="compliant", integrator_options={
        "relative_tolerance": 1e-12, "absolute_tolerance": 1e-18})
    simulation.run(0.0, 2e-4)  # the contact lasts at most 7e-5 s at 89 degrees
    return np.array(velocity), np.array(sphere.velocity)


def psi(tangential, normal):
    """Maw, Barber & Fawcett's variable of a tangential velocity at an incident normal speed."""
    return LAMBDA / FRICTION * tangential / normal


def curve(angles):
    """psi_1, psi_2 and the normal restitution of each strike."""
    rows = []
    for degrees in angles:
        before, after = strike(degrees)
        slip_before, slip_after = before[0] + RADIUS * before[2], after[0] + RADIUS * after[2]
        rows.append((psi(slip_before, -before[1]), -psi(slip_after, -before[1]),
                     after[1] / -before[1]))
    return np.array(rows)


def against_lammps():
    """The worst difference over LAMMPS's strikes without spin, in velocity and r omega (m/s;
    LAMMPS's w_y is minus the planar angle's rate)."""
    data = np.loadtxt(LAMMPS, delimiter=",", skiprows=1)
    worst = 0.0
    for row in data[(data[:, 4:7] == 0.0).all(axis=1)]:
        _, after = strike(row[0])
        lammps = np.array([row[7], row[9], -row[11]])
        worst = max(worst, np.max(np.abs((after - lammps) * [1.0, 1.0, RADIUS])))
    return worst, data


def draw(rows, data, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, axes = plt.subplots(figsize=(7, 4.8))
    grid = np.linspace(0.0, rows[:, 0].max(), 400)
    axes.plot(grid, np.minimum(7.0 * LAMBDA - grid, 0.0), color="grey", linestyle="--",
              label="rigid tangential response (Stronge): rolling, then gross slip")
    axes.plot(rows[:, 0], rows[:, 1], color="C0", linewidth=1.8,
              label="mimpact: Hertz + Mindlin spring + Coulomb (compliant)")
    plain = data[(data[:, 4:7] == 0.0).all(axis=1)]
    lammps_psi1 = psi(plain[:, 1], -plain[:, 3])
    lammps_psi2 = -psi(plain[:, 7] - RADIUS * plain[:, 11], -plain[:, 3])
    axes.plot(lammps_psi1, lammps_psi2, "o", markerfacecolor="none", color="C3",
              label="LAMMPS pair granular mindlin, dt = 1.5625e-10 s")
    axes.axhline(0.0, color="black", linewidth=0.5)
    axes.set_xlabel(r"$\psi_1 = \frac{2(1-\nu)}{\mu(2-\nu)}\,\frac{v_t}{v_n}$ before")
    axes.set_ylabel(r"$\psi_2$ after (> 0: the contact point turned back)")
    axes.set_title("Oblique impact of an elastic sphere (Maw, Barber & Fawcett 1976)\n"
                   f"steel, r = {RADIUS * 1e3:g} mm, mu = {FRICTION:g}, e = 1, 1 m/s",
                   fontsize=10)
    axes.set_xlim(0.0, 12.0)
    axes.set_ylim(-5.0, 2.5)
    axes.legend(fontsize=8, loc="lower left")
    figure.tight_layout()
    out.mkdir(parents=True, exist_ok=True)
    figure.savefig(out / "maw_barber_fawcett.png", dpi=130)
    print(f"figure: {out / 'maw_barber_fawcett.png'}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="build/python-examples", help="directory of the PNG")
    out = pathlib.Path(parser.parse_args().out)
    rows = curve(np.concatenate([np.arange(0.5, 70.0, 0.5), np.arange(70.0, 89.5, 1.0)]))
    highest = np.argmax(rows[:, 1])
    reversed_ = rows[rows[:, 1] > 0.0, 0]
    print(f"reversal: psi_2 > 0 for psi_1 from {reversed_.min():.4f} to {reversed_.max():.4f}, "
          f"highest {rows[highest, 1]:.4f} at psi_1 {rows[highest, 0]:.4f}; "
          f"psi_2 / psi_1 at the smallest incidence {rows[0, 1] / rows[0, 0]:.4f}")
    slipping = rows[:, 0] > 7.0 * LAMBDA + 1.0
    print(f"gross slip: psi_2 - (7 lambda - psi_1) worst "
          f"{np.abs(rows[slipping, 1] + rows[slipping, 0] - 7.0 * LAMBDA).max():.2e} over "
          f"{slipping.sum()} strikes")
    print(f"normal restitution: worst |e_n - 1| {np.abs(rows[:, 2] - 1.0).max():.2e}")
    worst, data = against_lammps()
    print(f"against LAMMPS: worst {worst:.2e} m/s over 18 strikes")
    draw(rows, data, out)


if __name__ == "__main__":
    main()
