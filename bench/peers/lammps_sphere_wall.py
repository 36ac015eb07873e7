#!/usr/bin/python3
"""LAMMPS as the peer of mimpact's compliant contact with a Mindlin tangential spring: one sphere
striking a flat wall z = 0 obliquely, with Hertz normal force, Mindlin tangential spring and
Coulomb slip, no damping (`fix wall/gran granular hertz KN 0.0 tangential mindlin KT 0.0 MU
damping viscoelastic`, whose zero damping coefficient switches both dashpots off), integrated by
velocity Verlet (`fix nve/sphere`, I = 0.4 m r^2) at a fixed time step.

Needs Debian's LAMMPS (`apt-get install --no-install-recommends lammps`, binary /usr/bin/lmp,
stable 29 Sep 2021 update 2) and nothing else. Explicit KN and KT: that version's wall
`hertz/material` and `mindlin NULL` constants are not those of its pair style; the ones given are
LAMMPS's pair convention for a wall of the sphere's own material, kn = 4/3 E/(2 (1 - nu^2)) and
kt = 8 E/(4 (2 - nu)(1 + nu)), so that F_n = kn sqrt(r delta) delta and k_t = kt sqrt(r delta).

    lammps_sphere_wall.py --dt 1.5625e-10 --out sphere_on_wall_mindlin.csv

runs every case (the sphere touching the wall at t = 0, so that the touch lies on LAMMPS's time
grid: a touch between grid points costs LAMMPS an offset that no halving removes) for 8e-5 s, past
the contact's end, and writes one line per case: incidence (degrees from the normal), the velocity
and spin before (m/s, rad/s) and after.
"""
import argparse
import math
import os
import subprocess
import tempfile

RADIUS, DENSITY, YOUNG, POISSON, FRICTION = 0.005, 7780.0, 203e9, 0.3, 0.3

INPUT = """units si
dimension 3
boundary f f f
atom_style sphere
atom_modify map array
comm_modify vel yes
region box block -0.02 0.03 -0.02 0.03 -0.001 0.03 units box
create_box 1 box
create_atoms 1 single 0.0 0.0 {z!r} units box
set type 1 diameter {diameter!r}
set type 1 density {density!r}
set atom 1 vx {v[0]!r} vy {v[1]!r} vz {v[2]!r}
set atom 1 omega {w[0]!r} {w[1]!r} {w[2]!r}
pair_style none
fix integ all nve/sphere
fix wall all wall/gran granular hertz {kn!r} 0.0 tangential mindlin {kt!r} 0.0 {mu!r} &
    damping viscoelastic rolling none twisting none zplane 0.0 NULL
timestep {dt!r}
run {steps}
write_dump all custom final.dump id vx vy vz omegax omegay omegaz modify format float %.17g
"""


def cases():
    """Incidence 0 to 85 degrees in the x-z plane without spin; the same with a sideways
    velocity and a spin about every axis, whose slip turns in the tangent plane."""
    for spin in (False, True):
        for degrees in range(0, 90, 5):
            a = math.radians(degrees)
            v = [math.sin(a), 0.2 if spin else 0.0, -math.cos(a)]
            w = [20.0, -40.0, 30.0] if spin else [0.0, 0.0, 0.0]
            yield degrees, v, w


def run(dt, v, w):
    kn = 4.0 / 3.0 * YOUNG / (2.0 * (1.0 - POISSON**2))
    kt = 8.0 * YOUNG / (4.0 * (2.0 - POISSON) * (1.0 + POISSON))
    with tempfile.TemporaryDirectory() as work:
        with open(os.path.join(work, "in.wall"), "w") as f:
            f.write(INPUT.format(z=RADIUS, diameter=2 * RADIUS, density=DENSITY, v=v, w=w, kn=kn,
                                 kt=kt, mu=FRICTION, dt=dt, steps=int(round(8e-5 / dt))))
        subprocess.run(["lmp", "-nocite", "-in", "in.wall", "-log", "none", "-screen", "none"],
                       cwd=work, check=True)
        with open(os.path.join(work, "final.dump")) as f:
            return [float(x) for x in f.read().split("\n")[9].split()[1:]]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--dt", type=float, required=True, help="time step, s")
    parser.add_argument("--out", required=True, help="CSV written")
    args = parser.parse_args()
    with open(args.out, "w") as out:
        out.write("incidence_deg,vx,vy,vz,wx,wy,wz,vx_after,vy_after,vz_after,"
                  "wx_after,wy_after,wz_after\n")
        for degrees, v, w in cases():
            after = run(args.dt, v, w)
            out.write(",".join(repr(x) for x in [degrees, *v, *w, *after]) + "\n")


if __name__ == "__main__":
    main()
