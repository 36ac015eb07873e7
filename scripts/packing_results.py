"""The physics of planar packings (issue 12, item d), run with `mimpact packing` and drawn into
docs/results/packings/: force chains of a struck hexagonal packing, the peak force along its two
lattice directions, the wave speed against the peak force along a lattice line, and a square
packing struck along its diagonal. Writes docs/results/packings.md with the measured figures.

    /usr/bin/python3 scripts/packing_results.py --mimpact build/release/bin/mimpact
"""

import argparse
import json
import os
import subprocess
import tempfile

import importlib.util

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# the package's reader of `mimpact packing --out`, pure Python: loaded from its file, so that the
# compiled module need not be built
_spec = importlib.util.spec_from_file_location(
    "packing_output", os.path.join(ROOT, "python", "mimpact", "packing_output.py"))
packing_output = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(packing_output)

import matplotlib  # noqa: E402
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STEEL = {"density": 7780, "young": 203e9, "poisson": 0.3}  # C1's (docs/experiments.md)
RADIUS = 0.005
OUT = os.path.join(ROOT, "docs", "results", "packings")


def run(mimpact, scene, work, name):
    """Runs a scene, written into `work`, with --out; returns the output directory."""
    path = os.path.join(work, name + ".json")
    with open(path, "w") as stream:
        json.dump(scene, stream)
    out = os.path.join(work, name)
    subprocess.run([mimpact, "packing", path, "--out", out, "--quiet"], check=True)
    return out


def hexagon_scene(rows, columns, speed, frames=0, interval=2e-7):
    scene = {
        "material": STEEL,
        "lattice": {"type": "hexagonal", "rows": rows, "columns": columns, "radius": RADIUS},
        "strikers": [{"target": [0, columns // 2], "radius": RADIUS, "velocity": [0.0, speed]}],
        "impact": {"integrator": "adaptive", "tolerance": 1e-8},
    }
    if frames:
        scene["record"] = {"interval": interval, "frames": frames}
    return scene


def lattice_line(rows, columns, start, step):
    """The beads of a lattice line of a hexagonal packing from bead (0, start): `step` +1 goes
    up and right (60 degrees), -1 up and left (120 degrees). Row r's odd rows are shifted by a,
    so going up-right from an even row keeps the column and from an odd row adds one."""
    beads, column = [], start
    for r in range(rows):
        if not 0 <= column < columns:
            break
        beads.append(r * columns + column)
        odd = r % 2 == 1
        column += (1 if odd else 0) if step > 0 else (0 if odd else -1)
    return beads


def contact_index(data, a, b):
    pairs = {(int(f), int(s)): j for j, (f, s) in enumerate(zip(data["first"], data["second"]))}
    return pairs.get((min(a, b), max(a, b)))


def along_line(data, beads):
    """Distance (m) from the struck bead, peak force (N) and its time (s) of each contact of a
    lattice line."""
    contacts = data["summary"]["contacts"]
    rows = []
    for k in range(len(beads) - 1):
        j = contact_index(data, beads[k], beads[k + 1])
        rows.append(((k + 0.5) * 2 * RADIUS, contacts[j]["max_force"], contacts[j]["time_of_max"]))
    return np.array(rows)


def force_chains(mimpact, work, lines):
    rows, columns = 24, 31
    out = run(mimpact, hexagon_scene(rows, columns, 1.0, frames=20, interval=5e-7), work,
              "hexagon_frames")
    data = packing_output.load(out)
    # four instants as the front crosses the packing
    wanted = [4e-5, 1.5e-4, 2.5e-4, 3.5e-4]
    frames = [int(np.argmin(abs(data["time"] - t))) for t in wanted]
    figure, panels = plt.subplots(1, 4, figsize=(14, 3.9))
    segments = packing_output.contact_segments(data)
    widest = max(data["force"][f].max() for f in frames)
    from matplotlib.collections import LineCollection
    for panel, frame in zip(panels, frames):
        for centre in data["centre"]:
            panel.add_patch(plt.Circle(centre, RADIUS, fill=False, lw=0.2, color="0.7"))
        panel.add_collection(LineCollection(segments, linewidths=5.0 * data["force"][frame] / widest,
                                            colors="firebrick"))
        start = data["centre"][columns // 2]
        for angle in (60, 120):  # the two lattice directions, +-30 degrees from the strike
            d = np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle))])
            panel.plot(*np.transpose([start, start + 0.3 * d]), "--", color="steelblue", lw=0.6)
        panel.set_aspect("equal")
        panel.set_xlim(data["centre"][:, 0].min() - RADIUS, data["centre"][:, 0].max() + RADIUS)
        panel.set_ylim(data["centre"][:, 1].min() - 3 * RADIUS, data["centre"][:, 1].max() + RADIUS)
        panel.set_axis_off()
        panel.set_title(f"t = {1e6 * data['time'][frame]:.0f} µs", fontsize=9)
    figure.suptitle(f"{rows} x {columns} hexagonal packing struck from below at 1 m/s: contact "
                    "forces, width ∝ force; dashed, the lattice directions at ±30°", fontsize=10)
    figure.tight_layout()
    figure.savefig(os.path.join(OUT, "force_chains.png"), dpi=130)
    plt.close(figure)

    # peak force along each lattice direction
    summary_path = run(mimpact, hexagon_scene(rows, columns, 1.0), work, "hexagon")
    data = packing_output.load(summary_path)
    figure, axis = plt.subplots(figsize=(5.5, 4))
    for step, label in ((1, "+30° (up and right)"), (-1, "−30° (up and left)")):
        line = along_line(data, lattice_line(rows, columns, columns // 2, step))
        axis.plot(1e3 * line[:, 0], line[:, 1], "o-", ms=3, label=label)
        lines[label] = line
    axis.set_xlabel("distance from the struck bead along the line (mm)")
    axis.set_ylabel("peak contact force (N)")
    axis.set_yscale("log")
    axis.legend()
    axis.set_title("peak force along the lattice directions", fontsize=10)
    figure.tight_layout()
    figure.savefig(os.path.join(OUT, "peak_force_along_lines.png"), dpi=130)
    plt.close(figure)
    peak_force_map(data)
    return on_and_off_lines(data, rows, columns)


def peak_force_map(data):
    """Every contact drawn in the colour of its peak force."""
    from matplotlib.collections import LineCollection
    force = np.array([c["max_force"] for c in data["summary"]["contacts"]])
    figure, axis = plt.subplots(figsize=(7, 5))
    drawn = LineCollection(1e3 * packing_output.contact_segments(data),
                           array=np.log10(np.maximum(force, 1e-3)), cmap="inferno_r", linewidths=2)
    axis.add_collection(drawn)
    figure.colorbar(drawn, label="log10 of the peak force (N)")
    axis.set_aspect("equal")
    axis.autoscale_view()
    axis.set_xlabel("x (mm)")
    axis.set_ylabel("y (mm)")
    axis.set_title("peak force of every contact", fontsize=10)
    figure.tight_layout()
    figure.savefig(os.path.join(OUT, "peak_force_map.png"), dpi=130)
    plt.close(figure)


def on_and_off_lines(data, rows, columns):
    """Per row r, the peak force of the two lattice lines' contacts from row r to r + 1, and the
    largest of the other contacts between those rows."""
    force = np.array([c["max_force"] for c in data["summary"]["contacts"]])
    on_line = set()
    for step in (1, -1):
        beads = lattice_line(rows, columns, columns // 2, step)
        on_line.update(contact_index(data, beads[k], beads[k + 1]) for k in range(len(beads) - 1))
    table = []
    beads = rows * columns
    for r in range(0, rows - 1, 3):
        between = [j for j, (a, b) in enumerate(zip(data["first"], data["second"]))
                   if 0 <= b < beads and a // columns == r and b // columns == r + 1]
        table.append((r, max(force[j] for j in between if j in on_line),
                      max(force[j] for j in between if j not in on_line)))
    return table


def speed_law(mimpact, work):
    """Wave speed against peak force along the +30° lattice line, for strikes from 0.01 to
    3 m/s; fitted V = c F^alpha over contacts 3 to 8 of the line."""
    rows, columns = 20, 25
    speeds, forces = [], []
    for striker in (0.01, 0.03, 0.1, 0.3, 1.0, 3.0):
        data = packing_output.load(run(mimpact, hexagon_scene(rows, columns, striker), work,
                                       f"speed_{striker}"))
        line = along_line(data, lattice_line(rows, columns, columns // 2, 1))[3:9]
        # speed between consecutive contacts 2a apart, from their times of peak force
        speeds.append(2 * RADIUS * (len(line) - 1) / (line[-1, 2] - line[0, 2]))
        forces.append(line[:, 1].mean())
    alpha, log_c = np.polyfit(np.log(forces), np.log(speeds), 1)
    figure, axis = plt.subplots(figsize=(5.5, 4))
    axis.loglog(forces, speeds, "o", label="mimpact, adaptive LZB")
    f = np.geomspace(min(forces), max(forces), 50)
    axis.loglog(f, np.exp(log_c) * f ** alpha, "-", label=f"fit: V ∝ F^{alpha:.3f}")
    axis.loglog(f, speeds[0] * (f / forces[0]) ** (1 / 6), ":", label="V ∝ F^(1/6)")
    axis.set_xlabel("peak force along the lattice line (N)")
    axis.set_ylabel("wave speed along the line (m/s)")
    axis.legend()
    axis.set_title("wave speed against peak force, +30° line", fontsize=10)
    figure.tight_layout()
    figure.savefig(os.path.join(OUT, "speed_against_force.png"), dpi=130)
    plt.close(figure)
    return alpha, speeds, forces


def diagonal(mimpact, work):
    rows = columns = 10
    scene = {
        "material": STEEL,
        "lattice": {"type": "square", "rows": rows, "columns": columns, "radius": RADIUS},
        "strikers": [{"target": [0, 0], "radius": RADIUS,
                      "velocity": [1 / np.sqrt(2), 1 / np.sqrt(2)]}],
        "impact": {"integrator": "adaptive", "tolerance": 1e-8},
    }
    data = packing_output.load(run(mimpact, scene, work, "diagonal"))
    velocity = np.array(data["summary"]["post_impact_velocities"])[: rows * columns]
    speed = np.linalg.norm(velocity, axis=1)
    on_lines = [k for k in range(rows * columns) if k // columns == 0 or k % columns == 0]
    others = max(speed[k] for k in range(rows * columns) if k not in on_lines)
    figure, axis = plt.subplots(figsize=(4.8, 4.4))
    shown = axis.scatter(data["centre"][: rows * columns, 0] * 1e3,
                         data["centre"][: rows * columns, 1] * 1e3, c=speed, s=160,
                         cmap="viridis", edgecolors="0.5", linewidths=0.3)
    figure.colorbar(shown, label="speed after the impact (m/s)")
    axis.set_aspect("equal")
    axis.set_xlabel("x (mm)")
    axis.set_ylabel("y (mm)")
    axis.set_title("square packing, corner struck along the diagonal", fontsize=10)
    figure.tight_layout()
    figure.savefig(os.path.join(OUT, "diagonal_strike.png"), dpi=130)
    plt.close(figure)
    return others, speed[columns - 1], speed[(rows - 1) * columns]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mimpact", default=os.path.join(ROOT, "build/release/bin/mimpact"))
    arguments = parser.parse_args()
    os.makedirs(OUT, exist_ok=True)
    with tempfile.TemporaryDirectory() as work:
        lines = {}
        table = force_chains(arguments.mimpact, work, lines)
        alpha, speeds, forces = speed_law(arguments.mimpact, work)
        others, row_end, column_end = diagonal(arguments.mimpact, work)
    report = {"alpha": alpha, "speeds": speeds, "forces": forces, "others": others,
              "row_end": row_end, "column_end": column_end, "on_and_off_lines": table,
              "lines": {k: v.tolist() for k, v in lines.items()}}
    print(json.dumps({k: report[k] for k in ("alpha", "others", "row_end", "column_end")}))
    with open(os.path.join(OUT, "measured.json"), "w") as stream:
        json.dump(report, stream, indent=1)


if __name__ == "__main__":
    main()
