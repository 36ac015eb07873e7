#!/usr/bin/python3
"""Runs bench_packing_peers (built in Release) once and writes docs/PAGE.md and
docs/performance/PAGE.png (PAGE: performance_packings by default): time against error for
mimpact's compliant contacts in the moving geometry and for LAMMPS, on the same packings, in one
benchmark run. Every number of the page comes from that run.

    /usr/bin/python3 bench/packing_work_precision.py --bench build/release/bench/bench_packing_peers \
        [--scenes 0,1] [--page performance_packings] [--install-lammps]

Scenes (bench_packing_peers.cpp): 0 hexagonal 32 x 32 to 1 ms, 1 hexagonal 56 x 56 to 1.75 ms,
2 hexagonal 100 x 100 to 3.1 ms, 3 FCC 20 x 20 x 20 to 0.5 ms, 4 FCC 10 x 10 x 10 to 0.25 ms,
5 hexagonal 32 x 32 with friction (mu 0.3, Mindlin's spring) to 1 ms, 6 FCC 6 x 6 x 6 with the
same friction to 0.3 ms (docs/performance_friction.md is --scenes 5,6 --page
performance_friction). Without LAMMPS (/usr/bin/lmp) its runs are skipped
with a message, and the page says so; --install-lammps installs Debian's.
"""
import argparse
import json
import math
import os
import platform
import subprocess
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
CODES = {"Mimpact": "mimpact, moving geometry (over its tolerance)",
         "Lammps": "LAMMPS, velocity Verlet (over its step)"}
TARGETS = (1e-4, 1e-6)


def run(bench, scenes, out):
    """One run of both families on `scenes`, saved as JSON in `out`."""
    pattern = "^BM_Packing(Mimpact|Lammps)/(" + "|".join(str(s) for s in scenes) + ")/"
    subprocess.run([bench, f"--benchmark_filter={pattern}", "--benchmark_format=console",
                    f"--benchmark_out={out}", "--benchmark_out_format=json"], check=True)


def parse(out):
    """The saved run: its context, {scene: {code: [rows]}} and the skip messages."""
    data = json.loads(Path(out).read_text())
    scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}
    results, skipped = {}, []
    for b in data["benchmarks"]:
        code = b["name"].split("/")[0].replace("BM_Packing", "")
        if b.get("error_occurred"):
            skipped.append(b.get("error_message", "skipped"))
            continue
        knob = (f"dt = {b['dt']:.3g} s" if code == "Lammps"
                else f"tolerance {b['name'].split('/')[2]}")
        results.setdefault(b["label"], {}).setdefault(code, []).append(
            {"seconds": b["real_time"] * scale[b["time_unit"]], "rms": b["rms_error"],
             "worst": b["worst_error"], "knob": knob, "bodies": int(b["bodies"]),
             "contacts": b.get("contacts_loaded"), "duration": b.get("duration"),
             "body_steps": b.get("body_steps")})
    return data["context"], results, sorted(set(skipped))


def time_at(rows, target, field="seconds"):
    """The time (s) a code needs for an RMS error of `target` (or another `field` of its runs),
    and whether it is a bound: interpolated log-log between the two runs that bracket it; when
    even the code's cheapest run is more accurate, that run's time bounds it (True); None when
    no run reaches it."""
    points = sorted((r["rms"], r[field]) for r in rows if r["rms"] > 0 and r.get(field))
    if not points:
        return None, False
    for (e1, t1), (e2, t2) in zip(points, points[1:]):
        if e1 <= target <= e2:
            w = (math.log(target) - math.log(e1)) / (math.log(e2) - math.log(e1))
            return math.exp(math.log(t1) + w * (math.log(t2) - math.log(t1))), False
    if target > points[-1][0]:
        return min(t for _, t in points), True
    return None, False


def shown_time(time, bound):
    if time is None:
        return "not reached"
    return ("≤ " if bound else "") + f"{time:.3g}"


def shown_ratio(m, m_bound, lammps, lammps_bound):
    if m is None or lammps is None or (m_bound and lammps_bound):
        return "—"
    return ("≥ " if m_bound else "≤ " if lammps_bound else "") + f"{lammps / m:.2f}"


def figure(results, png):
    columns = min(3, len(results))
    rows = math.ceil(len(results) / columns)
    fig, panels = plt.subplots(rows, columns, figsize=(5.2 * columns, 4.2 * rows), squeeze=False)
    for panel in panels.flat[len(results):]:
        panel.set_visible(False)
    for panel, (scene, codes) in zip(panels.flat, results.items()):
        for code, rows in codes.items():
            rows = sorted(rows, key=lambda r: -r["rms"])  # joined in order of accuracy
            marker, color = ("s", "tab:green") if code == "Mimpact" else ("o", "tab:gray")
            panel.loglog([r["rms"] for r in rows], [r["seconds"] for r in rows], marker=marker,
                         color=color, label=CODES[code] + ", RMS")
            panel.loglog([r["worst"] for r in rows], [r["seconds"] for r in rows],
                         marker=marker, color=color, ls=":", mfc="none",
                         label=CODES[code] + ", worst bead")
        panel.set_xlabel("error of the velocities at the end time, relative to V")
        panel.set_ylabel("time (s)")
        panel.set_title(scene)
        panel.grid(True, which="both", alpha=0.3)
        panel.invert_xaxis()
    panels[0][0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=130)
    plt.close(fig)


def cost_table(results):
    """Issue 24, item c: mimpact's time per contact that carried force and per millisecond of the
    run, at each decade of tolerance, scene by scene."""
    tolerances = sorted({r["knob"] for codes in results.values() for r in codes.get("Mimpact", [])
                         if r.get("contacts") and r["knob"].startswith("tolerance 1e-")},
                        key=lambda k: -float(k.split()[-1]))
    if not tolerances:
        return []
    lines = ["## What the cost follows", "",
             "mimpact's time per contact that carried force and per millisecond of the run "
             "(µs), and its bodies' steps per contact and millisecond, at each tolerance: "
             "flat across sizes when the cost follows what moves.", "",
             "| scene | contacts loaded | run (ms) | " +
             " | ".join(t.replace("tolerance ", "tol ") for t in tolerances) + " | body steps (tol 1e-4) |",
             "|---|---|---|" + "---|" * len(tolerances) + "---|"]
    for scene, codes in results.items():
        rows = {r["knob"]: r for r in codes.get("Mimpact", []) if r.get("contacts")}
        if not rows:
            continue
        any_row = next(iter(rows.values()))
        per = lambda r: r["seconds"] * 1e6 / (r["contacts"] * r["duration"] * 1e3)
        cells = [f"{per(rows[t]):.0f}" if t in rows else "—" for t in tolerances]
        steps = rows.get("tolerance 1e-4")
        lines.append(f"| {scene} | {any_row['contacts']:.0f} | {any_row['duration'] * 1e3:g} | " +
                     " | ".join(cells) + " | " +
                     (f"{steps['body_steps'] / (steps['contacts'] * steps['duration'] * 1e3):.0f}"
                      if steps else "—") + " |")
    return lines + [""] + fixed_accuracy_table(results)


def fixed_accuracy_table(results):
    """Item c as it reads, at a fixed accuracy: the time and the body steps per contact and
    millisecond that each scene needs for an RMS error, interpolated between its runs as the
    times above (where a scene's loosest run is already more accurate, '≤' that run's), and
    LAMMPS's time per contact and millisecond for the same error beside them."""
    targets = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
    lines = ["At a fixed accuracy: mimpact's time (µs) and its bodies' steps per contact and "
             "millisecond, then LAMMPS's time (µs) per contact and millisecond, for an RMS "
             "error of the velocities, each interpolated between the runs that bracket it. "
             "A larger packing runs longer and its wake rattles more: the same local error "
             "grows into a larger final one, for both codes alike.", "",
             "| scene | " + " | ".join(f"RMS {t:g}" for t in targets) + " |",
             "|---|" + "---|" * len(targets)]
    for scene, codes in results.items():
        rows = [r for r in codes.get("Mimpact", []) if r.get("contacts")]
        if not rows:
            continue
        scale = 1.0 / (rows[0]["contacts"] * rows[0]["duration"] * 1e3)
        cells = []
        for target in targets:
            time, time_bound = time_at(rows, target)
            steps, _ = time_at(rows, target, "body_steps")
            lammps, lammps_bound = time_at(codes.get("Lammps", []), target)
            cell = "—" if time is None or steps is None else \
                ("≤ " if time_bound else "") + f"{time * 1e6 * scale:.0f} / {steps * scale:.0f}"
            cell += " / " + ("—" if lammps is None else
                             ("≤ " if lammps_bound else "") + f"{lammps * 1e6 * scale:.0f}")
            cells.append(cell)
        lines.append(f"| {scene} | " + " | ".join(cells) + " |")
    return lines + [""]


def page(context, results, skipped, png, command):
    lines = ["# Packings: mimpact against LAMMPS, time against accuracy", "",
             f"Written by `{command}` from one run of `bench/bench_packing_peers.cpp` on "
             f"{platform.node()} ({context.get('num_cpus')} CPUs, {context.get('date')}). "
             "Both codes integrate the same beads (steel, a = 5 mm, struck at 1 m/s by an "
             "equal bead, e = 1) with the same Hertz law; each error is that of the bodies' "
             "velocities at the end time against mimpact at tolerance 1e-10, relative to the "
             "striker's speed: the RMS over the bodies and the worst body. mimpact's time is "
             "its run's (`wall_time` in summary.json: neighbour lists and integration; the "
             "scene's parsing and the lattice's building excluded), LAMMPS's its own loop "
             "time (its start-up, neighbour lists included, excluded); each the least "
             "of three runs where a run takes under a second." +
             (" A scene with μ gives both codes Mindlin's tangential spring under Coulomb's "
              "cap (LAMMPS's `tangential mindlin`, k_t = 8 G* a), the beads spinning; its "
              "errors take the larger of a bead's velocity's and r times its spin's."
              if any("mu" in scene for scene in results) else ""), "",
             f"![time against error](performance/{png.name})", ""]
    if skipped:
        lines += ["Runs that did not finish: " + "; ".join(skipped) + ".", ""]
    for scene, codes in results.items():
        lines += [f"## {scene}", "", "| target RMS error | mimpact (s) | LAMMPS (s) | LAMMPS / mimpact |",
                  "|---|---|---|---|"]
        for target in TARGETS:
            m, m_bound = time_at(codes.get("Mimpact", []), target)
            lammps, lammps_bound = time_at(codes.get("Lammps", []), target)
            lines.append(f"| {target:g} | {shown_time(m, m_bound)} | "
                         f"{shown_time(lammps, lammps_bound)} | "
                         f"{shown_ratio(m, m_bound, lammps, lammps_bound)} |")
        lines += ["", "| code | setting | time (s) | RMS error | worst bead |", "|---|---|---|---|---|"]
        for code, rows in codes.items():
            for r in sorted(rows, key=lambda r: r["seconds"]):
                lines.append(f"| {code.lower()} | {r['knob']} | {r['seconds']:.3g} | "
                             f"{r['rms']:.2e} | {r['worst']:.2e} |")
        lines.append("")
    return "\n".join(lines + cost_table(results))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bench", required=True)
    parser.add_argument("--scenes", default="0", help="comma-separated scene numbers")
    parser.add_argument("--page", default="performance_packings",
                        help="the page's name: docs/PAGE.md, docs/performance/PAGE.png")
    parser.add_argument("--install-lammps", action="store_true")
    parser.add_argument("--reuse", action="store_true", help="redraw from the last run's JSON")
    args = parser.parse_args()
    if args.install_lammps and not os.path.exists("/usr/bin/lmp"):
        subprocess.run(["apt-get", "install", "-y", "--no-install-recommends", "lammps"],
                       check=True)
    if not os.path.exists("/usr/bin/lmp"):
        print("LAMMPS is not installed: its runs are skipped (--install-lammps installs it)")
    out = ROOT / "build" / f"{args.page}.json"
    if not args.reuse:
        run(args.bench, [int(s) for s in args.scenes.split(",")], out)
    context, results, skipped = parse(out)
    png = ROOT / "docs" / "performance" / ("packings_work_precision.png"
                                           if args.page == "performance_packings"
                                           else f"{args.page}.png")
    png.parent.mkdir(exist_ok=True)
    figure(results, png)
    command = "/usr/bin/python3 bench/packing_work_precision.py --bench " \
              f"build/release/bench/bench_packing_peers --scenes {args.scenes}" + \
              ("" if args.page == "performance_packings" else f" --page {args.page}")
    (ROOT / "docs" / f"{args.page}.md").write_text(
        page(context, results, skipped, png, command) + "\n")
    print(ROOT / "docs" / f"{args.page}.md")


if __name__ == "__main__":
    main()
