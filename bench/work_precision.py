#!/usr/bin/python3
"""Runs bench_work_precision (built in Release) and writes docs/performance.md with its two
figures: the work-precision diagrams (one run of the benchmark's WorkPrecision family) and the
cost against the chain's length (one run of its ChainLength family). Every number in the page
comes from those two runs.

    /usr/bin/python3 bench/work_precision.py --bench build/release/bench/bench_work_precision
"""
import argparse
import json
import math
import platform
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
CASES = {"C1": "C1: 20 beads, e = 1", "C2": "C2: 20 tapered beads, e = 1",
         "N": "N: Nakagawa, 19 tapered beads, e = 0.955", "M2": "M type 2: 30 beads, e = 0.965",
         "chain1000": "1 000 beads (C1's), e = 1"}
TARGETS = (1e-2, 1e-4, 1e-6)
METHODS = ("impulse", "adaptive", "compliant")
NAMES = {"impulse": "LZB impulse steps", "adaptive": "adaptive LZB", "compliant": "compliant"}
KNOBS = {"impulse": "over ΔP", "adaptive": "over its tolerance", "compliant": "over its tolerance"}
MARKERS = {"impulse": "o", "adaptive": "^", "compliant": "s"}
COLORS = {"impulse": "tab:blue", "adaptive": "tab:orange", "compliant": "tab:green"}
LENGTH_SETTINGS = {"impulse": "ΔP = 1e-4 m V", "adaptive": "tolerance 1e-6", "compliant": "tolerance 1e-6"}


def run_family(bench, family, out, reuse):
    """One run of a benchmark family (or, with reuse, the run saved in `out`); returns the
    benchmark's context and its rows {parts of the name, seconds, counters}."""
    if not reuse:
        subprocess.run([bench, f"--benchmark_filter=^{family}/", "--benchmark_format=console",
                        f"--benchmark_out={out}", "--benchmark_out_format=json"], check=True)
    data = json.loads(out.read_text())
    scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}
    rows = []
    for b in data["benchmarks"]:
        parts = b["name"].split("/")
        rows.append({"parts": parts, "seconds": b["real_time"] * scale[b["time_unit"]], **b})
    return data["context"], rows


def curves(rows):
    """{case: {method: [(seconds, velocity error, force error, knob, steps)] in knob order}}."""
    result = {}
    for r in rows:
        _, case, method, _knob = r["parts"][:4]
        if r["velocity_error"] == 0.0:  # the run is the reference itself
            continue
        result.setdefault(case, {}).setdefault(method, []).append(
            (r["seconds"], r["velocity_error"], r["force_error"], r["knob"], r["steps"]))
    for methods in result.values():
        for points in methods.values():
            points.sort(key=lambda p: -p[3])  # coarse to fine
    return result


def time_to_reach(points, column, target):
    """Wall time at which the error (column 1 or 2) falls to target, along the runs that no
    faster run beats (the Pareto front), interpolated in log-log between the two around it.
    Returns (seconds, how): how is 'measured', 'at most' (the fastest run is already better)
    or 'not reached'."""
    front = []
    for p in sorted(points, key=lambda p: p[0]):
        if not front or p[column] < front[-1][column]:
            front.append(p)
    if front[0][column] <= target:
        return front[0][0], "at most"
    for before, after in zip(front, front[1:]):
        if after[column] <= target:
            e0, e1 = math.log(before[column]), math.log(after[column])
            t0, t1 = math.log(before[0]), math.log(after[0])
            w = (math.log(target) - e0) / (e1 - e0)
            return math.exp(t0 + w * (t1 - t0)), "measured"
    return None, "not reached"


def extrapolated_impulse(points, column, target):
    """The impulse steps' time for an accuracy beyond their sweep: first order, so time x error
    is constant along the finest runs."""
    finest = min(points, key=lambda p: p[column])
    return finest[0] * finest[column] / target


def cost_exponent(points):
    """The fitted slope of log(time) against log(velocity error) along the Pareto front."""
    front = []
    for p in sorted(points, key=lambda p: p[0]):
        if not front or p[1] < front[-1][1]:
            front.append(p)
    return float(np.polyfit(np.log([p[1] for p in front]), np.log([p[0] for p in front]), 1)[0])


def cell(seconds, how, floor):
    if seconds is None:
        return f"not reached (best {floor:.1e})"
    text = f"{1e3 * seconds:.3g} ms" if seconds < 1 else f"{seconds:.3g} s"
    return {"at most": "≤ " + text, "extrapolated": "≈ " + text + " (extrapolated)"}.get(how, text)


def ratio_text(ratio):
    return f"{ratio:.3g}" if ratio < 100 else f"{ratio:.0f}"


def fastest(times):
    """Which method reaches the accuracy first, and by how much against the next. When the
    next one's time is its fastest run ('at most'), the ratio is against that run."""
    reached = sorted((m for m in METHODS if times[m][0] is not None), key=lambda m: times[m][0])
    if not reached:
        return "none"
    if len(reached) == 1:
        return NAMES[reached[0]]
    first, second = reached[:2]
    ratio = ratio_text(times[second][0] / times[first][0])
    if times[second][1] == "at most":
        return f"{NAMES[first]}, ×{ratio} on the next one's fastest run"
    if "extrapolated" in (times[first][1], times[second][1]):
        return f"{NAMES[first]}, ×{ratio} (extrapolated)"
    return f"{NAMES[first]}, ×{ratio}"


def work_precision_figure(data, path):
    fig, axes = plt.subplots(2, 3, figsize=(13, 7.5))
    for ax, case in zip(axes.flat, CASES):
        for method in METHODS:
            points = data[case][method]
            t = [p[0] for p in points]
            label = f"{NAMES[method]} {KNOBS[method]}"
            marker = MARKERS[method]
            ax.loglog(t, [p[1] for p in points], marker + "-", ms=4, color=COLORS[method],
                      label=label + ", velocities")
            ax.loglog(t, [p[2] for p in points], marker + "--", ms=3, mfc="none", color=COLORS[method],
                      label=label + ", peak forces")
        for target in TARGETS:
            ax.axhline(target, color="0.8", lw=0.6, zorder=0)
        ax.set_title(CASES[case], fontsize=9)
        ax.set_xlabel("wall time of a run (s)")
        ax.set_ylabel("relative error")
    axes.flat[-1].axis("off")
    handles, labels = axes.flat[0].get_legend_handles_labels()
    axes.flat[-1].legend(handles, labels, loc="center", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def chain_length_figure(rows, path):
    lengths = {}
    for r in rows:
        _, method, beads = r["parts"][:3]
        lengths.setdefault(method, []).append((int(beads), r["seconds"], r["steps"], r["last_velocity"]))
    fits = {}
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    for method in METHODS:
        points = sorted(lengths[method])
        n = np.array([p[0] for p in points], dtype=float)
        t = np.array([p[1] for p in points])
        long_enough = n >= 100
        fits[method] = np.polyfit(np.log(n[long_enough]), np.log(t[long_enough]), 1)[0]
        ax.loglog(n, t, MARKERS[method] + "-", color=COLORS[method],
                  label=f"{NAMES[method]}, {LENGTH_SETTINGS[method]}: time ∝ n^{fits[method]:.2f}")
    ax.set_xlabel("beads n")
    ax.set_ylabel("wall time of the impact (s)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return lengths, fits


def packing_section(scale_json):
    """The cost of planar packings' impacts against their size, from scripts/packing_scale.py's
    runs (a separate study: its runs take about ten minutes); empty before it has run."""
    if not scale_json.exists():
        return ""
    sizes = json.loads(scale_json.read_text())
    rows = ["| beads | contacts reached | contacts per step | impulse steps, ΔP = 1e-7 N s: time | "
            "its error (m/s) | the largest ΔP within 1e-4: ΔP, time | adaptive LZB at 1e-4: time, error |",
            "|---|---|---|---|---|---|---|"]
    for size in sizes:
        runs = size["runs"]
        steps = [r for r in runs if r["method"] == "impulse steps"]
        middle = next(r for r in steps if r["delta_p"] == 1e-7)
        within = [r for r in steps if r["error"] <= 1e-4]
        target = f"{within[0]['delta_p']:g} N s, {within[0]['wall_time']:.3g} s" if within else "—"
        adaptive = [r for r in runs if r["method"] == "adaptive LZB"]
        adaptive = (f"{adaptive[0]['wall_time']:.3g} s, {adaptive[0]['error']:.1e}" if adaptive
                    else "not run")
        rows.append(f"| {size['beads']} | {middle['contacts_reached']} of {middle['contacts']} | "
                    f"{middle['contacts_per_step']:.0f} | {middle['wall_time']:.3g} s | "
                    f"{middle['error']:.1e} | {target} | {adaptive} |")
    return f"""
## Planar packings

Hexagonal packings of steel beads struck at the middle of one edge
(`PYTHONPATH=build/release/python /usr/bin/python3 scripts/packing_scale.py --full`, which
writes [results/packing_scale.md](results/packing_scale.md) with every run; `bench_packing`
times the same impacts). The error is against the impulse steps Richardson-extrapolated from
their two finest runs. The contacts per step grow with the contacts the wave reaches, but the
impact lasts longer in a larger packing and the wake behind the front stays loaded, so the
impulse steps' time at a given accuracy grows faster than the contacts reached. The adaptive
LZB's follows them: its elastic switches stay within its steps (docs/design/adaptive_lzb.md).

{chr(10).join(rows)}
"""


def packing_peers_section(peers_page):
    """Packings against LAMMPS, at the two RMS errors of issue 24, from the page that
    bench/packing_work_precision.py writes (a separate study: twenty minutes with LAMMPS);
    empty before it has run."""
    if not peers_page.exists():
        return ""
    targets = ("0.0001", "1e-06")
    found, scene = {}, None
    for line in peers_page.read_text().splitlines():
        if line.startswith("## "):
            scene = line[3:]
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if scene and len(cells) == 4 and cells[0] in targets:
            found.setdefault(scene, {})[cells[0]] = cells[1:]
    rows = ["| scene | RMS 1e-4: mimpact (s) | LAMMPS (s) | LAMMPS / mimpact | "
            "RMS 1e-6: mimpact (s) | LAMMPS (s) | LAMMPS / mimpact |",
            "|---|---|---|---|---|---|---|"]
    for scene, at in found.items():
        rows.append(f"| {scene} | " + " | ".join(" | ".join(at.get(t, ["—"] * 3)) for t in targets)
                    + " |")
    return f"""
## Packings against LAMMPS

The packings as they really move (the compliant contacts in the moving geometry, docs/model.md
section 17) and LAMMPS (Debian's `lammps`, the same Hertz law, velocity Verlet) on the same
beads struck at 1 m/s, in one benchmark run (`/usr/bin/python3 bench/packing_work_precision.py
--bench build/release/bench/bench_packing_peers --scenes 0,1,2,3,4 --install-lammps`, which writes
[performance_packings.md](performance_packings.md) with every run, its figure and the cost per
contact that carried force): each code's time for an RMS error of the velocities at the end
time, against mimpact at tolerance 1e-10, interpolated between its runs (mimpact's at two
tolerances a decade, LAMMPS's at steps a factor 2 apart). This machine's speed
drifts by up to half again over minutes and the study reads each point once;
docs/design/moving_geometry.md, "Cost", gives the points around 1e-6 run five times each.

{chr(10).join(rows)}
"""


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bench", help="the bench_work_precision executable")
    parser.add_argument("--out", default=str(ROOT / "docs"), help="where performance.md and its figures go")
    parser.add_argument("--work", default=str(ROOT / "build" / "work-precision"), help="the benchmark's JSON")
    parser.add_argument("--reuse", action="store_true", help="rewrite the page from the runs saved in --work")
    args = parser.parse_args()
    out, work = Path(args.out), Path(args.work)
    (out / "performance").mkdir(parents=True, exist_ok=True)
    work.mkdir(parents=True, exist_ok=True)

    context, rows = run_family(args.bench, "WorkPrecision", work / "work_precision.json", args.reuse)
    data = curves(rows)
    work_precision_figure(data, out / "performance" / "work_precision.png")
    table = ["| chain | accuracy | " + " | ".join(f"{NAMES[m]}: velocities" for m in METHODS) + " | fastest | "
             + " | ".join(f"{NAMES[m]}: peak forces" for m in METHODS) + " | fastest |",
             "|---|---|" + "---|" * (2 * len(METHODS) + 2)]
    verdicts = {target: [] for target in TARGETS}
    times = {}
    for case in CASES:
        for target in TARGETS:
            cells = []
            for column in (1, 2):
                reached = {m: time_to_reach(data[case][m], column, target) for m in METHODS}
                if reached["impulse"][0] is None:
                    reached["impulse"] = (extrapolated_impulse(data[case]["impulse"], column, target), "extrapolated")
                floors = {m: min(p[column] for p in data[case][m]) for m in METHODS}
                verdict = fastest(reached)
                if column == 1:
                    verdicts[target].append((case, verdict))
                    times[(case, target)] = reached
                cells += [cell(*reached[m], floors[m]) for m in METHODS] + [verdict]
            table.append(f"| {case} | {target:.0e} | " + " | ".join(cells) + " |")

    _, length_rows = run_family(args.bench, "ChainLength", work / "chain_length.json", args.reuse)
    lengths, fits = chain_length_figure(length_rows, out / "performance" / "chain_length.png")
    length_table = ["| beads | " + " | ".join(f"{NAMES[m]}: time | steps" for m in METHODS)
                    + " | last bead's speed, " + " / ".join(NAMES[m] for m in METHODS) + " (m/s) |",
                    "|---|" + "---|" * (2 * len(METHODS) + 1)]
    by_length = {m: {p[0]: p for p in lengths[m]} for m in METHODS}
    for n in sorted(by_length["impulse"]):
        runs = [by_length[m][n] for m in METHODS]
        length_table.append(f"| {n} | " + " | ".join(f"{cell(r[1], 'measured', 0)} | {r[2]:.0f}" for r in runs)
                            + " | " + " / ".join(f"{r[3]:.6f}" for r in runs) + " |")
    largest = max(by_length["impulse"])
    last_speeds = [by_length[m][largest][3] for m in METHODS]
    spread = max(last_speeds) - min(last_speeds)
    ten_times = {m: by_length[m][10000][1] / by_length[m][1000][1] for m in METHODS}

    exponents = {m: ", ".join(f"{cost_exponent(data[c][m]):.2f}" for c in CASES) for m in METHODS}
    c1_adaptive, c1_impulse = times[("C1", 1e-6)]["adaptive"], times[("C1", 1e-6)]["impulse"]
    m2_floor = min(p[1] for p in data["M2"]["compliant"])

    def summary(target):
        counts = {}
        for case, verdict in verdicts[target]:
            counts.setdefault(verdict.split(",")[0].split(" (")[0], []).append(case)
        return "; ".join(f"{method}: {', '.join(cases)}" for method, cases in sorted(counts.items()))

    machine = f"{context.get('num_cpus', '?')} CPUs at {context.get('mhz_per_cpu', '?')} MHz, {platform.system()}"
    page = f"""# Speed against accuracy

Written by `bench/work_precision.py` from two runs of `bench/bench_work_precision.cpp` (Google
Benchmark, Release build, {machine}, one core):

    bash scripts/work-precision.sh

The work-precision diagrams come from one run of the `WorkPrecision` family, the cost against
the chain's length from one run of `ChainLength`. A run is a whole impact through the kernel, as
`mimpact chain` does it, by one of three methods: the LZB impulse steps (event-driven scheme, one
multiple impact) with ΔP a share of the striker's momentum m V, from 1e-2 down to 1e-6; the
adaptive LZB integrator (the same model's continuous limit, Dormand-Prince 5(4), every switch
located; docs/model.md §10) at tolerances 1e-2 to 1e-10; the compliant contacts integrated in
time (Dormand-Prince 5(4), contact events located, bodies in free flight in closed form;
docs/model.md §11) at relative tolerances 1e-4 (its loosest) to 1e-10. The error is ‖x − x_ref‖∞ / ‖x_ref‖∞
over the post-impact velocities, and over every contact's largest force. The reference is, for
e = 1, the compliant method at tolerance 1e-12 (1e-10 for the 1 000 beads): the Hertz chain,
which LZB converges to; for e < 1, where the two laws differ on re-loading (docs/model.md §3),
the impulse steps Richardson-extrapolated from ΔP = 1e-6 and 5e-7 m V, themselves about 1e-7
from LZB's limit. The compliant runs of the 1 000-bead chain stop at 0.032 s, after the wave has
left (0.0297 s): behind the wave the beads come to rest touching, so their contacts never all open.

![work-precision](performance/work_precision.png)

Time to reach a relative accuracy, interpolated in log-log between the two runs around it on
the Pareto front (the runs no faster run beats); "≤" when the fastest run is already better;
for the impulse steps beyond their sweep, extrapolated at first order from the finest run
("≈"); "not reached" when a method never gets there (with the best error it reached).

{chr(10).join(table)}

Fastest at 1e-2 relative accuracy of the post-impact velocities: {summary(1e-2)}.
Fastest at 1e-4: {summary(1e-4)}. Fastest at 1e-6: {summary(1e-6)}.

Why: the impulse steps are first order in ΔP and their cost is the number of steps, ΣP / ΔP,
so their time goes as the error to the power {exponents['impulse']} (fitted slope of log time
against log error, per chain). The adaptive LZB integrator and the compliant method are of
fifth order: their times go as the error to the powers {exponents['adaptive']} and
{exponents['compliant']}. On C1, 1e-6 takes the adaptive integrator {cell(*c1_adaptive, 0)}, and
the impulse steps {cell(*c1_impulse, 0)}: ×{ratio_text(c1_impulse[0] / c1_adaptive[0])}. Where e < 1
the adaptive integrator is LZB itself, and its curve meets the impulse steps' limit; the
compliant method stops {m2_floor:.1e} from it on M2, the two laws differing where a contact
re-loads.

## Cost against the length of the chain

C1's beads, n of them, struck at one end; the impulse steps at ΔP = 1e-4 m V, the adaptive and
compliant methods at tolerance 1e-6, each until the wave has left the chain (2e-4 s + 3.2e-5 s a
bead; the last column checks it). Fitted over n ≥ 100, the time of the impulse steps grows as
n^{fits['impulse']:.2f}, that of the adaptive integrator as n^{fits['adaptive']:.2f} and that of
the compliant method as n^{fits['compliant']:.2f}: the work of a step is that of the few contacts
(or bodies) the wave holds, never the whole chain's. From 1 000 to 10 000 beads the time grows
×{ten_times['impulse']:.1f}, ×{ten_times['adaptive']:.1f} and ×{ten_times['compliant']:.1f}.
A tolerance bounds the error each step adds, and along a chain the steps' errors add up: at
tolerance 1e-6 the three methods' speeds of the last of {largest} beads spread over
{spread:.1e} m/s (the last column); a 100 000-bead chain needs a tolerance of about 1e-9 to be
right to 1e-6 (docs/model.md §10).

![chain length](performance/chain_length.png)

{chr(10).join(length_table)}
""" + packing_section(ROOT / "docs" / "results" / "packings" / "scale.json") + \
        packing_peers_section(ROOT / "docs" / "performance_packings.md")
    (out / "performance.md").write_text(page)
    print(f"wrote {out / 'performance.md'}", file=sys.stderr)


if __name__ == "__main__":
    main()
