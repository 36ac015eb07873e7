#!/usr/bin/python3
"""LAMMPS as a peer for mimpact's work-precision study: beads with a pure Hertz normal law
F = K delta^1.5 (frictionless, undamped, e = 1), integrated by LAMMPS's velocity Verlet
(`fix nve/sphere`) at a fixed time step.

Needs Debian's LAMMPS (`apt-get install --no-install-recommends lammps`, binary /usr/bin/lmp,
stable 29 Sep 2021 update 2) and python3-numpy; nothing else.

Bodies CSV: header `x,y,z,radius,mass,vx,vy,vz` (SI; z = vz = 0 in 2-D), one body a line.
Run it:

    lammps_packing.py --bodies B.csv --dimension 2 --hertz-k K --dt 1e-7 --end-time 3e-4 \\
        --out final.csv [--ref ref.csv --speed 1]

Or generate a hexagonal packing struck by a bead (mimpact's convention: bead (row r, column c)
is body r*columns + c, centre (2a c + a (r mod 2), sqrt(3) a r); the striker is the last body,
touching its target on the side it comes from) and, if --dt is given, run it:

    lammps_packing.py --hexagonal 10 10 --radius 0.005 --young 203e9 --poisson 0.3 \\
        --density 7780 --strike 0 5 --speed 1 --bodies B.csv [--dt ... --end-time ... --out ...]

One run prints a JSON line {"dt", "steps", "loop_time_s", "atoms", ...}; `loop_time_s` is
LAMMPS's own `Loop time of X on 1 procs`. With --ref (final velocities of a finer run, same
bodies), it adds the error |v - v_ref| / V: RMS over all bodies and the worst body.

Every pair of bodies gets F = K delta^1.5 with the one K given (--hertz-k, or from the material
with --hexagonal): LAMMPS's `hertz` normal model is F = k_n sqrt(R_eff) delta^1.5, so each
pair of radius classes gets its own `pair_coeff i j hertz K/sqrt(R_eff)`, R_eff = R_i R_j/(R_i+R_j).

`--selftest` checks the physics on two beads head-on (velocity exchange, Hertz contact time).
"""
import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np

COLUMNS = ("x", "y", "z", "radius", "mass", "vx", "vy", "vz")
LMP = shutil.which("lmp") or "/usr/bin/lmp"


def fmt(x):
    """A float with all its digits (round-trips exactly through strtod)."""
    return repr(float(x))


# ---------------------------------------------------------------------------- bodies
def read_bodies(path):
    with open(path) as f:
        header = [c.strip() for c in f.readline().strip().split(",")]
        if tuple(header) != COLUMNS:
            sys.exit(f"{path}: header must be {','.join(COLUMNS)}, found {','.join(header)}")
        rows = [[float(c) for c in line.split(",")] for line in f if line.strip()]
    data = np.array(rows, dtype=float).reshape(-1, len(COLUMNS))
    return {name: data[:, i] for i, name in enumerate(COLUMNS)}


def write_bodies(path, bodies):
    n = len(bodies["x"])
    with open(path, "w") as f:
        f.write(",".join(COLUMNS) + "\n")
        for i in range(n):
            f.write(",".join(fmt(bodies[c][i]) for c in COLUMNS) + "\n")


def hertz_k(young, poisson, radius):
    """K = (4/3) E* sqrt(R*) of two equal beads, as mimpact's hertz_stiffness computes it."""
    e_star = 1.0 / ((1.0 - poisson * poisson) / young + (1.0 - poisson * poisson) / young)
    r_star = radius * radius / (radius + radius)
    return 4.0 / 3.0 * math.sqrt(r_star) * e_star


def bead_mass(radius, density):
    """As granular/src/hertz.cpp computes it (same rounding)."""
    return 4.0 / 3.0 * math.pi * radius * radius * radius * density


def hexagonal(rows, columns, a, density, strike, speed):
    """Beads at rest on mimpact's hexagonal lattice, then one striker of the same bead with
    velocity (0, speed) touching bead `strike` = (row, column) on the side it comes from."""
    mass = bead_mass(a, density)
    row_pitch = math.sqrt(3.0) * a  # as packings/src/packing_model.cpp
    xs, ys = [], []
    for r in range(rows):
        for c in range(columns):
            shift = a if r % 2 == 1 else 0.0
            xs.append(2.0 * a * c + shift)
            ys.append(row_pitch * r)
    target = strike[0] * columns + strike[1]
    if not (0 <= strike[0] < rows and 0 <= strike[1] < columns):
        sys.exit(f"--strike {strike}: no such bead in {rows} x {columns}")
    direction = 1.0 if speed > 0 else -1.0  # velocity (0, speed): it comes from below if speed > 0
    xs.append(xs[target])
    ys.append(ys[target] - (a + a) * direction)
    n = len(xs)
    vy = np.zeros(n)
    vy[-1] = speed
    return {"x": np.array(xs), "y": np.array(ys), "z": np.zeros(n), "radius": np.full(n, a),
            "mass": np.full(n, mass), "vx": np.zeros(n), "vy": vy, "vz": np.zeros(n)}


# ---------------------------------------------------------------------------- LAMMPS input
def lammps_input(bodies, dimension, k, dt, steps, skin, trace=None, damping=0.0, friction=None):
    """The data file and the input script. `trace` = (i, j, every): print the distance of
    bodies i and j (0-based) every `every` steps in the thermo output. `friction` = (mu, kt):
    Mindlin's tangential spring k_t = kt a under Coulomb's cap mu F_n (`tangential mindlin`,
    its dashpot off with the normal one's: damping viscoelastic with 0)."""
    n = len(bodies["x"])
    radii = sorted(set(bodies["radius"].tolist()))
    type_of = {r: t + 1 for t, r in enumerate(radii)}
    lo = [min(bodies[c]) - 4 * max(radii) for c in "xyz"]
    hi = [max(bodies[c]) + 4 * max(radii) for c in "xyz"]
    if dimension == 2:
        if np.any(bodies["z"] != 0.0) or np.any(bodies["vz"] != 0.0):
            sys.exit("--dimension 2 needs z = vz = 0 for every body")
        lo[2], hi[2] = -0.5, 0.5  # thin periodic z, as LAMMPS's Howto_2d asks
    data = ["mimpact bodies for LAMMPS (lammps_packing.py)", "",
            f"{n} atoms", f"{len(radii)} atom types", "",
            f"{fmt(lo[0])} {fmt(hi[0])} xlo xhi", f"{fmt(lo[1])} {fmt(hi[1])} ylo yhi",
            f"{fmt(lo[2])} {fmt(hi[2])} zlo zhi", "", "Atoms # sphere", ""]
    # atom-ID type diameter density x y z; the density is overwritten by `set atom .. mass`
    for i in range(n):
        r = bodies["radius"][i]
        data.append(f"{i + 1} {type_of[r]} {fmt(2.0 * r)} 1.0 {fmt(bodies['x'][i])} "
                    f"{fmt(bodies['y'][i])} {fmt(bodies['z'][i])}")
    data += ["", "Velocities", ""]
    for i in range(n):
        data.append(f"{i + 1} {fmt(bodies['vx'][i])} {fmt(bodies['vy'][i])} "
                    f"{fmt(bodies['vz'][i])} 0.0 0.0 0.0")
    data.append("")

    inp = ["# written by bench/peers/lammps_packing.py",
           "units si",
           f"dimension {dimension}",
           "boundary m m p" if dimension == 2 else "boundary m m m",
           "atom_style sphere",
           "atom_modify map array",
           "comm_modify vel yes",
           "read_data bodies.data"]
    masses = bodies["mass"]
    if np.all(masses == masses[0]):
        inp.append(f"set group all mass {fmt(masses[0])}")
    else:
        inp += [f"set atom {i + 1} mass {fmt(m)}" for i, m in enumerate(masses)]
    inp.append("pair_style granular")
    for ri in radii:
        for rj in radii:
            if type_of[rj] < type_of[ri]:
                continue
            r_eff = ri * rj / (ri + rj)
            tangential = ("tangential linear_nohistory 0.0 0.0" if friction is None else
                          f"tangential mindlin {fmt(friction[1])} 0.0 {fmt(friction[0])} "
                          "damping viscoelastic")
            inp.append(f"pair_coeff {type_of[ri]} {type_of[rj]} hertz {fmt(k / math.sqrt(r_eff))} "
                       f"{fmt(damping)} {tangential}")
    inp += [f"neighbor {fmt(skin)} bin",
            "neigh_modify delay 0 every 1 check yes",
            "fix integrate all nve/sphere"]
    if dimension == 2:
        inp.append("fix planar all enforce2d")  # the last fix
    inp.append(f"timestep {fmt(dt)}")
    if trace:
        i, j, every = trace
        inp += [f"variable dist equal sqrt((x[{j + 1}]-x[{i + 1}])^2+(y[{j + 1}]-y[{i + 1}])^2"
                f"+(z[{j + 1}]-z[{i + 1}])^2)",
                "thermo_style custom step v_dist", "thermo_modify format float %.17g",
                f"thermo {every}"]
    else:
        inp += ["thermo_style custom step ke", f"thermo {steps}"]
    inp += [f"run {steps}",
            "write_dump all custom final.txt id vx vy vz omegax omegay omegaz x y z "
            "modify sort id format float %.17g"]
    return "\n".join(data), "\n".join(inp) + "\n"


def run_lammps(bodies, dimension, k, dt, end_time, skin=None, trace=None, keep=None,
               damping=0.0, friction=None):
    steps = round(end_time / dt)
    if steps < 1 or abs(steps * dt - end_time) > 1e-9 * end_time:
        sys.exit(f"--end-time {end_time} is not a whole number of steps of --dt {dt}")
    if skin is None:
        skin = 0.2 * float(max(bodies["radius"]))
    data, inp = lammps_input(bodies, dimension, k, dt, steps, skin, trace, damping, friction)
    work = keep or tempfile.mkdtemp(prefix="lammps_packing_")
    os.makedirs(work, exist_ok=True)
    with open(os.path.join(work, "bodies.data"), "w") as f:
        f.write(data)
    with open(os.path.join(work, "in.packing"), "w") as f:
        f.write(inp)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    proc = subprocess.run([LMP, "-nocite", "-in", "in.packing", "-log", "log.lammps",
                           "-screen", "none"], cwd=work, env=env,
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    log = open(os.path.join(work, "log.lammps")).read() if os.path.exists(
        os.path.join(work, "log.lammps")) else ""
    if proc.returncode != 0 or "ERROR" in log:
        sys.stderr.write(proc.stdout + log[-3000:])
        sys.exit(f"lmp failed (rc {proc.returncode}); files in {work}")
    m = re.search(r"Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms", log)
    if not m or int(m.group(3)) != steps:
        sys.exit(f"no 'Loop time' line for {steps} steps in {work}/log.lammps")
    warnings = [line for line in log.splitlines() if line.startswith("WARNING")]
    final = np.loadtxt(os.path.join(work, "final.txt"), skiprows=9, ndmin=2)
    final = final[np.argsort(final[:, 0])]
    dist = None
    if trace:
        dist = []
        for line in log.split("\nStep")[1].splitlines()[1:]:
            parts = line.split()
            if len(parts) != 2 or not parts[0].isdigit():
                break
            dist.append((int(parts[0]), float(parts[1])))
    if keep is None:
        shutil.rmtree(work)
    return {"dt": dt, "steps": steps, "loop_time_s": float(m.group(1)), "atoms": int(m.group(4)),
            "v": final[:, 1:4], "omega": final[:, 4:7],
            "omega_max": float(np.max(np.abs(final[:, 4:7]))),
            "x": final[:, 7:10],
            "warnings": warnings, "dist": dist, "input": inp}


def write_velocities(path, v):
    with open(path, "w") as f:
        f.write("vx,vy,vz\n")
        for row in v:
            f.write(",".join(fmt(c) for c in row) + "\n")


def read_velocities(path):
    return np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


def errors(v, ref, speed):
    d = np.linalg.norm(v - ref, axis=1) / speed
    return float(np.sqrt(np.mean(d ** 2))), float(np.max(d)), int(np.argmax(d))


# ---------------------------------------------------------------------------- self-test
def selftest():
    """Two equal steel beads head-on at 1 m/s (one at rest), 2-D."""
    a, E, nu, rho, V = 0.005, 203e9, 0.3, 7780.0, 1.0
    K = hertz_k(E, nu, a)
    m = bead_mass(a, rho)
    m_star = m / 2.0
    delta_max = (5.0 * m_star * V * V / (4.0 * K)) ** 0.4
    # t_c = 2 delta_max / V * int_0^1 dx / sqrt(1 - x^2.5) = 2.94320 delta_max / V
    integral = 0.4 * math.gamma(0.4) * math.gamma(0.5) / math.gamma(0.9)  # 1.4716376
    tc_theory = 2.0 * integral * delta_max / V  # = 3.21807 (m*^2 / (K^2 V))^(1/5)
    tc_brief = 2.868 * (m_star ** 2 / (K ** 2 * V)) ** 0.2
    bodies = {"x": np.zeros(2), "y": np.array([0.0, 2 * a]), "z": np.zeros(2),
              "radius": np.full(2, a), "mass": np.full(2, m), "vx": np.zeros(2),
              "vy": np.array([V, 0.0]), "vz": np.zeros(2)}
    print(json.dumps({"K": K, "mass": m, "delta_max": delta_max, "tc_hertz": tc_theory,
                      "tc_2.868_K_formula": tc_brief, "tc_2.868_EstarRstar":
                      2.868 * (m_star ** 2 / ((K * 0.75) ** 2 * V)) ** 0.2}))
    for steps_per_tc in (25, 100, 400, 1600, 6400, 25600):
        dt = tc_theory / steps_per_tc
        steps = 4 * steps_per_tc
        r = run_lammps(bodies, 2, K, dt, steps * dt, trace=(0, 1, 1))
        d = np.array(r["dist"])
        t, gap = d[:, 0] * dt, d[:, 1] - 2 * a
        inside = np.nonzero(gap < 0)[0]
        i1 = inside[-1]
        # the contact opens at t = 0 exactly (gap 0, approaching); it closes between steps i1
        # and i1 + 1 (linear interpolation of the gap)
        t_close = t[i1] + (t[i1 + 1] - t[i1]) * (-gap[i1]) / (gap[i1 + 1] - gap[i1])
        t_open = 0.0
        v = r["v"]
        print(json.dumps({"dt": dt, "steps": steps, "loop_time_s": r["loop_time_s"],
                          "v_striker": v[0].tolist(), "v_target": v[1].tolist(),
                          "exchange_error": float(max(abs(v[0, 1] - 0.0), abs(v[1, 1] - V),
                                                      abs(v[0, 0]), abs(v[1, 0]))) / V,
                          "max_overlap": float(-gap.min()),
                          "overlap_rel": float(-gap.min() / delta_max),
                          "t_contact": t_close - t_open,
                          "t_contact_rel": (t_close - t_open) / tc_theory - 1.0,
                          "omega_max": r["omega_max"], "warnings": r["warnings"]}))
    # the 0.0 after k_n is the damping slot (default model viscoelastic, F = eta a m_eff v_n,
    # a = sqrt(R delta)): 1e7 there must lose energy, so 0.0 is what turns damping off
    dt = tc_theory / 1600
    r = run_lammps(bodies, 2, K, dt, 6400 * dt, damping=1e7)
    v = r["v"]
    print(json.dumps({"damping_check": 1e7, "restitution": float((v[1, 1] - v[0, 1]) / V)}))
    return 0


# ---------------------------------------------------------------------------- main
def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--bodies", help="bodies CSV (read; written with --hexagonal)")
    p.add_argument("--dimension", type=int, choices=(2, 3), default=2)
    p.add_argument("--hertz-k", type=float, help="K in F = K delta^1.5 (N/m^1.5), every pair")
    p.add_argument("--dt", type=float)
    p.add_argument("--end-time", type=float)
    p.add_argument("--out", help="final velocities CSV (vx,vy,vz, body order)")
    p.add_argument("--out-positions", help="final positions CSV (x,y,z, body order)")
    p.add_argument("--out-spins", help="final angular velocities CSV (wx,wy,wz, body order)")
    p.add_argument("--friction", type=float, help="Coulomb's mu with Mindlin's tangential "
                   "spring (default: frictionless)")
    p.add_argument("--mindlin-kt", type=float, help="kt in k_t = kt sqrt(R* delta) (Pa): 8 G*; "
                   "with --young and --poisson, 8 E / (4 (2 - nu)(1 + nu)) of one material")
    p.add_argument("--ref", help="final velocities of a reference run: report errors against it")
    p.add_argument("--speed", type=float, help="V for the errors |v - v_ref| / V "
                   "(default: the largest initial speed); with --hexagonal, the striker's")
    p.add_argument("--skin", type=float, help="neighbour skin (m), default 0.2 x largest radius")
    p.add_argument("--keep", help="keep LAMMPS's files (input, data, log) in this directory")
    p.add_argument("--center", action="store_true", help="shift the bodies so that their "
                   "bounding box is centred on 0 (smaller ulp of the positions: less round-off)")
    p.add_argument("--print-input", action="store_true", help="print the LAMMPS input to stderr")
    p.add_argument("--hexagonal", type=int, nargs=2, metavar=("ROWS", "COLUMNS"))
    p.add_argument("--radius", type=float)
    p.add_argument("--young", type=float)
    p.add_argument("--poisson", type=float)
    p.add_argument("--density", type=float)
    p.add_argument("--strike", type=int, nargs=2, metavar=("ROW", "COL"))
    p.add_argument("--selftest", action="store_true")
    args = p.parse_args()

    if args.selftest:
        return selftest()
    if not args.bodies:
        p.error("--bodies is needed")
    k = args.hertz_k
    if args.hexagonal:
        need = ("radius", "young", "poisson", "density", "strike", "speed")
        missing = [n for n in need if getattr(args, n) is None]
        if missing:
            p.error("--hexagonal needs " + ", ".join("--" + n for n in missing))
        bodies = hexagonal(*args.hexagonal, args.radius, args.density, args.strike, args.speed)
        write_bodies(args.bodies, bodies)
        k_material = hertz_k(args.young, args.poisson, args.radius)
        if k is not None and abs(k / k_material - 1) > 1e-12:
            p.error(f"--hertz-k {k} differs from the material's K = {k_material}")
        k = k_material
        if args.dt is None:
            print(json.dumps({"bodies": args.bodies, "count": len(bodies["x"]), "hertz_k": k,
                              "mass": float(bodies["mass"][0])}))
            return 0
    else:
        bodies = read_bodies(args.bodies)
    if args.center:
        for c in "xyz":
            bodies[c] = bodies[c] - 0.5 * (bodies[c].min() + bodies[c].max())
    if k is None or args.dt is None or args.end_time is None:
        p.error("a run needs --hertz-k (or --hexagonal ...), --dt and --end-time")
    friction = None
    if args.friction:
        kt = args.mindlin_kt
        if kt is None and args.young and args.poisson is not None:
            kt = 8.0 * args.young / (4.0 * (2.0 - args.poisson) * (1.0 + args.poisson))
        if kt is None:
            p.error("--friction needs --mindlin-kt, or --young and --poisson")
        friction = (args.friction, kt)
    r = run_lammps(bodies, args.dimension, k, args.dt, args.end_time, args.skin, keep=args.keep,
                   friction=friction)
    if args.print_input:
        sys.stderr.write(r["input"])
    if args.out:
        write_velocities(args.out, r["v"])
    if args.out_spins:
        with open(args.out_spins, "w") as f:
            f.write("wx,wy,wz\n")
            f.writelines(",".join(fmt(c) for c in row) + "\n" for row in r["omega"])
    if args.out_positions:
        with open(args.out_positions, "w") as f:
            f.write("x,y,z\n")
            f.writelines(",".join(fmt(c) for c in row) + "\n" for row in r["x"])
    result = {"dt": r["dt"], "steps": r["steps"], "loop_time_s": r["loop_time_s"],
              "atoms": r["atoms"], "hertz_k": k, "omega_max": r["omega_max"]}
    if r["warnings"]:
        result["warnings"] = r["warnings"]
    if args.ref:
        speed = args.speed or float(np.max(np.linalg.norm(
            np.stack([bodies["vx"], bodies["vy"], bodies["vz"]], axis=1), axis=1)))
        rms, worst, body = errors(r["v"], read_velocities(args.ref), speed)
        result.update({"rms_error": rms, "worst_error": worst, "worst_body": body})
    print(json.dumps(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
