#!/usr/bin/python3
"""LAMMPS as the peer of mimpact's compliant contacts with a Mindlin tangential spring: a steel
sphere striking a flat wall z = 0, or a sphere at rest, obliquely, with Hertz normal force,
Mindlin tangential spring and Coulomb slip, no damping (`fix wall/gran granular hertz KN 0.0
tangential mindlin KT 0.0 MU damping viscoelastic`, or the same `pair_coeff` of `pair_style
granular`; a zero damping coefficient switches both dashpots off), integrated by velocity Verlet
(`fix nve/sphere`, I = 0.4 m r^2) at a fixed time step.

Needs Debian's LAMMPS (`apt-get install --no-install-recommends lammps`, binary /usr/bin/lmp,
stable 29 Sep 2021 update 2) and nothing else. Explicit KN and KT: that version's wall
`hertz/material` and `mindlin NULL` constants are not those of its pair style; the ones given are
LAMMPS's pair convention (a wall of the sphere's own material), kn = 4/3 E/(2 (1 - nu^2)) and
kt = 8 E/(4 (2 - nu)(1 + nu)), so that F_n = kn sqrt(R delta) delta and k_t = kt sqrt(R delta),
R the pair's effective radius (the sphere's against a wall).

    lammps_oblique.py --target wall --dt 1.5625e-10 --out sphere_on_wall_mindlin.csv
    lammps_oblique.py --target sphere --dt 1.5625e-10 --out sphere_on_sphere_mindlin.csv

runs every case (the spheres touching at t = 0, so that the touch lies on LAMMPS's time grid: a
touch between grid points costs LAMMPS an offset that no halving removes) for 8e-5 s, past the
contact's end, and writes one line per case: incidence (degrees from the line of centres), the
striker's velocity and spin before (m/s, rad/s) and after; against a sphere, that sphere's spin
before and its velocity and spin after too. The striker comes from below (z < 0) along +z.
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
region box block -0.02 0.03 -0.02 0.03 {bottom!r} 0.03 units box
create_box 1 box
{atoms}
set type 1 diameter {diameter!r}
set type 1 density {density!r}
set atom 1 vx {v[0]!r} vy {v[1]!r} vz {v[2]!r}
set atom 1 omega {w[0]!r} {w[1]!r} {w[2]!r}
{interaction}
fix integ all nve/sphere
timestep {dt!r}
run {steps}
write_dump all custom final.dump id vx vy vz omegax omegay omegaz modify format float %.17g
"""


TARGET_SPIN = [0.0, 10.0, -15.0]  # rad/s, of the struck sphere in the spinning cases


def cases(target):
    """Incidence 0 to 85 degrees in the x-z plane without spin; the same with a sideways
    velocity and a spin about every axis (and the struck sphere's own), whose slip turns in the
    tangent plane. Against the wall the striker comes down along -z."""
    down = -1.0 if target == "wall" else 1.0
    for spin in (False, True):
        for degrees in range(0, 90, 5):
            a = math.radians(degrees)
            v = [math.sin(a), 0.2 if spin else 0.0, down * math.cos(a)]
            w = [20.0, -40.0, 30.0] if spin else [0.0, 0.0, 0.0]
            yield degrees, v, w, (TARGET_SPIN if spin else [0.0, 0.0, 0.0])


def run(target, dt, v, w, target_spin):
    kn = 4.0 / 3.0 * YOUNG / (2.0 * (1.0 - POISSON**2))
    kt = 8.0 * YOUNG / (4.0 * (2.0 - POISSON) * (1.0 + POISSON))
    law = (f"hertz {kn!r} 0.0 tangential mindlin {kt!r} 0.0 {FRICTION!r} "
           "damping viscoelastic rolling none twisting none")
    if target == "wall":
        atoms = f"create_atoms 1 single 0.0 0.0 {RADIUS!r} units box"
        interaction = f"pair_style none\nfix wall all wall/gran granular {law} zplane 0.0 NULL"
    else:
        atoms = (f"create_atoms 1 single 0.0 0.0 {-2 * RADIUS!r} units box\n"
                 "create_atoms 1 single 0.0 0.0 0.0 units box")
        interaction = ("pair_style granular\npair_coeff * * " + law +
                       "\nset atom 2 omega " +
                       " ".join(repr(x) for x in target_spin))
    with tempfile.TemporaryDirectory() as work:
        with open(os.path.join(work, "in.oblique"), "w") as f:
            f.write(INPUT.format(bottom=-0.001 if target == "wall" else -0.03, atoms=atoms, interaction=interaction, diameter=2 * RADIUS,
                                 density=DENSITY, v=v, w=w, dt=dt, steps=int(round(8e-5 / dt))))
        subprocess.run(["lmp", "-nocite", "-in", "in.oblique", "-log", "none", "-screen", "none"],
                       cwd=work, check=True)
        with open(os.path.join(work, "final.dump")) as f:
            lines = f.read().split("\n")[9:]
            atoms_after = sorted((line.split() for line in lines if line.strip()),
                                 key=lambda row: int(row[0]))
            return [float(x) for row in atoms_after for x in row[1:]]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--target", choices=("wall", "sphere"), required=True)
    parser.add_argument("--dt", type=float, required=True, help="time step, s")
    parser.add_argument("--out", required=True, help="CSV written")
    args = parser.parse_args()
    with open(args.out, "w") as out:
        header = "incidence_deg,vx,vy,vz,wx,wy,wz"
        if args.target == "sphere":
            header += ",target_wx,target_wy,target_wz"
        header += ",vx_after,vy_after,vz_after,wx_after,wy_after,wz_after"
        if args.target == "sphere":
            header += (",target_vx_after,target_vy_after,target_vz_after,"
                       "target_wx_after,target_wy_after,target_wz_after")
        out.write(header + "\n")
        for degrees, v, w, target_spin in cases(args.target):
            after = run(args.target, args.dt, v, w, target_spin)
            before = [degrees, *v, *w] + (target_spin if args.target == "sphere" else [])
            out.write(",".join(repr(x) for x in before + after) + "\n")


if __name__ == "__main__":
    main()
