"""The cost of a planar packing's impact against its size and its accuracy (issue 12, item e).

Hexagonal packings of side x side steel beads, struck at the middle of the bottom edge at
1 m/s (bench_packing's scene), run by the impulse steps over halvings of delta_p, by the
asynchronous steps (docs/model.md, section 14) and by the adaptive LZB at tolerance 1e-4. The
error of each run is the largest difference of its
post-impact velocities from a Richardson extrapolation of the two finest impulse-step runs
(first order), in m/s of the 1 m/s strike (for the finest run, the difference from the one
before it: its own first-order estimate); the ratio of successive differences checks that
the runs are in the first-order regime. Writes docs/results/packing_scale.md and
docs/results/packings/scale.png.

    /usr/bin/python3 scripts/packing_scale.py            # sides 16, 32, 56: about 3 minutes
    /usr/bin/python3 scripts/packing_scale.py --full     # and 100 x 100: about 10 more

Run with the compiled module on the path (PYTHONPATH=build/release/python).
"""

import argparse
import json
import os

import numpy as np

import mimpact

import matplotlib  # noqa: E402
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "docs", "results")
STEEL = {"density": 7780, "young": 203e9, "poisson": 0.3}
DELTA_P = [4e-7, 2e-7, 1e-7, 5e-8, 2.5e-8]  # N s; the striker's momentum is 4.07e-3 N s
ASYNCHRONOUS_DELTA_P = [4e-7, 2e-7, 1e-7]  # N s
TOLERANCE = 1e-4  # the adaptive LZB's
TARGET = 1e-4  # the relative accuracy item e asks for


def scene(side, impact):
    return {"material": STEEL,
            "lattice": {"type": "hexagonal", "rows": side, "columns": side, "radius": 0.005},
            "strikers": [{"target": [0, side // 2], "radius": 0.005, "velocity": [0.0, 1.0]}],
            "impact": impact,
            # the LZB impact's cost alone: its check against the moving geometry is not timed
            "configuration_check": {"enabled": False}}


def measured(result):
    return {"wall_time": result.wall_time, "steps": result.steps,
            "contacts_per_step": result.contacts_per_step,
            "contacts_reached": int(np.count_nonzero(result.max_forces > 0.0)),
            "contacts": len(result.max_forces), "duration": result.duration}


def study(side):
    """The runs of one packing size, with their errors against the extrapolated answer."""
    runs = []
    velocities = []
    for delta_p in DELTA_P:
        result = mimpact.run_packing(scene(side, {"delta_p": delta_p}))
        runs.append({"method": "impulse steps", "delta_p": delta_p, **measured(result)})
        velocities.append(result.post_impact_velocities)
        print(side, runs[-1], flush=True)
    reference = 2.0 * velocities[-1] - velocities[-2]
    for run, v in zip(runs, velocities):
        run["error"] = float(np.abs(v - reference).max())
    differences = [float(np.abs(a - b).max()) for a, b in zip(velocities, velocities[1:])]
    for delta_p in ASYNCHRONOUS_DELTA_P:
        result = mimpact.run_packing(scene(side, {"integrator": "asynchronous",
                                                  "delta_p": delta_p}))
        runs.append({"method": "asynchronous steps", "delta_p": delta_p, **measured(result),
                     "error": float(np.abs(result.post_impact_velocities - reference).max())})
        print(side, runs[-1], flush=True)
    result = mimpact.run_packing(scene(side, {"integrator": "adaptive", "tolerance": TOLERANCE}))
    runs.append({"method": "adaptive LZB", "tolerance": TOLERANCE, **measured(result),
                 "error": float(np.abs(result.post_impact_velocities - reference).max())})
    print(side, runs[-1], flush=True)
    return {"side": side, "beads": side * side, "runs": runs,
            "halving_ratios": [a / b for a, b in zip(differences, differences[1:])]}


def wake(side, delta_p=2e-7, every=100):
    """The contacts in the impact against time, in frames of the impulse steps every `every`
    steps: all those carrying a force, and those above 1e-2 of the largest force then."""
    result = mimpact.run_packing({**scene(side, {"delta_p": delta_p}),
                                  "record": {"every": every, "frames": 1}})
    forces = result.frames["forces"][1:]
    largest = forces.max(axis=1)
    return {"side": side, "delta_p": delta_p, "time": result.frames["time"][1:].tolist(),
            "in_impact": np.count_nonzero(forces > 0.0, axis=1).tolist(),
            "loaded": np.count_nonzero(forces > 1e-2 * largest[:, None], axis=1).tolist(),
            "largest_force": largest.tolist(), "duration": result.duration,
            "impulse_sum": float(result.impulses.sum()),
            "contact_updates": result.steps * result.contacts_per_step}


def at_target(size, method="impulse steps"):
    """The cheapest run of `method` within TARGET, or None."""
    within = [r for r in size["runs"] if r["method"] == method and r["error"] <= TARGET]
    return min(within, key=lambda r: r["wall_time"]) if within else None


def draw(sizes, wakes, png):
    figure, (cost, accuracy, contacts) = plt.subplots(1, 3, figsize=(15, 4))
    for w in wakes:
        time = 1e6 * np.array(w["time"])
        line, = contacts.plot(time, w["in_impact"], label=f"{w['side']} x {w['side']}: in the impact")
        contacts.plot(time, w["loaded"], "--", color=line.get_color(),
                      label=f"{w['side']} x {w['side']}: above 1e-2 of the largest force")
    contacts.set_xlabel("time (us)")
    contacts.set_ylabel("contacts")
    contacts.set_title("contacts in the impact (impulse steps)")
    contacts.legend(fontsize=7)
    for size in sizes:
        steps = [r for r in size["runs"] if r["method"] == "impulse steps"]
        line, = accuracy.loglog([r["delta_p"] for r in steps], [r["error"] for r in steps],
                                "o-", label=f"{size['side']} x {size['side']}, impulse steps")
        kicks = [r for r in size["runs"] if r["method"] == "asynchronous steps"]
        accuracy.loglog([r["delta_p"] for r in kicks], [r["error"] for r in kicks], "s--",
                        color=line.get_color(), label=f"{size['side']} x {size['side']}, asynchronous")
    accuracy.axhline(TARGET, color="grey", lw=0.8)
    accuracy.set_xlabel("delta_p (N s)")
    accuracy.set_ylabel("largest velocity error (m/s)")
    accuracy.set_title("error against delta_p")
    accuracy.legend(fontsize=6)
    reached = [s["runs"][0]["contacts_reached"] for s in sizes]
    for delta_p in (2e-7, 1e-7):
        times = [next(r["wall_time"] for r in s["runs"] if r.get("delta_p") == delta_p)
                 for s in sizes]
        cost.loglog(reached, times, "o-", label=f"impulse steps, delta_p = {delta_p:g}")
    for method, marker in (("impulse steps", "s-"), ("asynchronous steps", "D-")):
        targets = [(s["runs"][0]["contacts_reached"], at_target(s, method)) for s in sizes]
        cost.loglog([c for c, r in targets if r], [r["wall_time"] for c, r in targets if r],
                    marker, label=f"{method} within {TARGET:g}")
    kicks = [next(r["wall_time"] for r in s["runs"]
                  if r["method"] == "asynchronous steps" and r["delta_p"] == 1e-7) for s in sizes]
    cost.loglog(reached, kicks, "D:", label="asynchronous steps, delta_p = 1e-07")
    adaptive = [(s["runs"][0]["contacts_reached"], r["wall_time"]) for s in sizes
                for r in s["runs"] if r["method"] == "adaptive LZB"]
    if adaptive:
        cost.loglog(*zip(*adaptive), "^-", label=f"adaptive LZB at {TOLERANCE:g}")
    line = np.array([reached[0], reached[-1]])
    first = next(r["wall_time"] for r in sizes[0]["runs"] if r.get("delta_p") == 1e-7)
    cost.loglog(line, first * line / line[0], "k:", lw=0.8, label="proportional to contacts reached")
    cost.set_xlabel("contacts the wave reaches")
    cost.set_ylabel("wall time of the impact (s)")
    cost.set_title("cost against size")
    cost.legend(fontsize=7)
    figure.tight_layout()
    figure.savefig(png, dpi=120)


def report(sizes, wakes):
    lines = ["# The cost of a planar packing's impact against its size (issue 12, item e)", "",
             "Written by `PYTHONPATH=build/release/python /usr/bin/python3 scripts/packing_scale.py"
             " --full` (Release, this 2-core machine): hexagonal packings of side x side steel"
             " beads (R = 5 mm), struck at the middle of the bottom edge at 1 m/s. The error is"
             " the largest difference of the post-impact velocities from the Richardson"
             " extrapolation of the two finest impulse-step runs (m/s, of a 1 m/s strike); for the"
             " finest run, that is its difference from the run before it.", "",
             "![cost and accuracy](packings/scale.png)", "",
             "| beads | method | delta_p or tolerance | steps | contacts per step | contacts reached"
             " of all | error (m/s) | time (s) |", "|---|---|---|---|---|---|---|---|"]
    for size in sizes:
        for r in size["runs"]:
            setting = f"{r['delta_p']:g} N s" if "delta_p" in r else f"{r['tolerance']:g}"
            error = f"{r['error']:.2e}"
            lines.append(f"| {size['beads']} | {r['method']} | {setting} | {r['steps']} | "
                         f"{r['contacts_per_step']:.0f} | {r['contacts_reached']} of "
                         f"{r['contacts']} | {error} | {r['wall_time']:.2f} |")
    lines += ["", "Ratios of successive differences under halving of delta_p (2 for first"
              " order):", ""]
    for size in sizes:
        ratios = ", ".join(f"{q:.2f}" for q in size["halving_ratios"])
        lines.append(f"- {size['beads']} beads: {ratios}")
    lines += ["", f"The cheapest impulse-step run within {TARGET:g} m/s:", ""]
    for size in sizes:
        r = at_target(size)
        lines.append(f"- {size['beads']} beads: " + (
            f"delta_p = {r['delta_p']:g} N s, {r['wall_time']:.1f} s" if r else
            f"none of delta_p >= {DELTA_P[-1]:g}"))
    lines += ["", f"The cheapest asynchronous run within {TARGET:g} m/s:", ""]
    for size in sizes:
        r = at_target(size, "asynchronous steps")
        lines.append(f"- {size['beads']} beads: " + (
            f"delta_p = {r['delta_p']:g} N s, {r['wall_time']:.1f} s" if r else
            f"none of delta_p >= {ASYNCHRONOUS_DELTA_P[-1]:g}"))
    lines += ["", f"The adaptive LZB at tolerance {TOLERANCE:g}, whose elastic switches stay within"
              " its steps (docs/design/adaptive_lzb.md), per contact reached and ms of the"
              " impact:", ""]
    for size in sizes:
        r = next(r for r in size["runs"] if r["method"] == "adaptive LZB")
        per_contact = r["wall_time"] / (r["contacts_reached"] * 1e3 * r["duration"])
        lines.append(f"- {size['beads']} beads: {r['wall_time']:.2f} s, error {r['error']:.2e}"
                     f" m/s, {1e6 * per_contact:.0f} us")
    lines += growth(sizes) + wake_lines(wakes)
    return "\n".join(lines) + "\n"


def growth(sizes):
    """What the time's growth from the second size to the largest is made of."""
    small, large = sizes[1], sizes[-1]
    a = next(r for r in small["runs"] if r.get("delta_p") == 1e-7)
    b = next(r for r in large["runs"] if r.get("delta_p") == 1e-7)
    per_contact_step = [r["wall_time"] / (r["steps"] * r["contacts_per_step"]) for r in (a, b)]
    target = [at_target(small), at_target(large)]
    lines = ["", f"## From {small['beads']} to {large['beads']} beads", "",
             f"- the contacts the wave reaches: x{b['contacts_reached'] / a['contacts_reached']:.1f};",
             f"- at delta_p = 1e-7 N s, the time: x{b['wall_time'] / a['wall_time']:.1f}, made of"
             f" the steps x{b['steps'] / a['steps']:.2f} (the impact lasts"
             f" {1e3 * a['duration']:.2f} ms, then {1e3 * b['duration']:.2f} ms), the contacts per"
             f" step x{b['contacts_per_step'] / a['contacts_per_step']:.1f} and the time per"
             f" contact and step x{per_contact_step[1] / per_contact_step[0]:.2f}"
             f" ({1e9 * per_contact_step[0]:.0f} then {1e9 * per_contact_step[1]:.0f} ns);",
             f"- at that delta_p the error grows x{b['error'] / a['error']:.1f}, so within"
             f" {TARGET:g} the time grows x{target[1]['wall_time'] / target[0]['wall_time']:.0f}"
             if all(target) else "- one size has no run within the target."]
    a, b = (next(r for r in s["runs"] if r["method"] == "asynchronous steps"
                 and r["delta_p"] == 1e-7) for s in (small, large))
    target = [at_target(small, "asynchronous steps"), at_target(large, "asynchronous steps")]
    lines += [f"- the asynchronous steps at delta_p = 1e-7 N s: the time x"
              f"{b['wall_time'] / a['wall_time']:.1f}, the kicks x{b['steps'] / a['steps']:.1f}"
              f" ({1e9 * a['wall_time'] / a['steps']:.0f} then"
              f" {1e9 * b['wall_time'] / b['steps']:.0f} ns a kick), the error"
              f" x{b['error'] / a['error']:.1f}"
              + (f"; within {TARGET:g}, the time x"
                 f"{target[1]['wall_time'] / target[0]['wall_time']:.1f}"
                 f" ({target[0]['wall_time']:.1f} s, then {target[1]['wall_time']:.1f} s)"
                 if all(target) else "; one size has no run within the target")]
    return lines


def wake_lines(wakes):
    lines = ["", "## The wake stays loaded", "",
             "The right-hand panel counts, in frames of the impulse steps (delta_p = 2e-7 N s),"
             " the contacts carrying a force and those above 1e-2 of the largest force at that"
             " instant. In a chain the beads behind the solitary wave come to rest, and the"
             " contacts in the impact are the few the wave holds. In the plane they are not:"
             " the striker's momentum spreads over the wedge the front has crossed, which keeps"
             " pushing the front, so the contacts behind it stay loaded until the wave has left"
             " the packing, and then unload slowly (a two-dimensional wave leaves a tail behind"
             " its front where a one-dimensional one does not). A contact far below the largest"
            " force moves by a small share of delta_p in each step, yet is updated in every step:"
            " the impulses of all contacts, counted in delta_p, are what the asynchronous steps,"
            " each contact kicking at its own pace, update.", ""]
    for w in wakes:
        peak = int(np.argmax(w["in_impact"]))
        lines.append(f"- {w['side']} x {w['side']}: at most {w['in_impact'][peak]} contacts in the"
                     f" impact, {w['loaded'][peak]} of them above 1e-2 of the largest force, at"
                     f" {1e6 * w['time'][peak]:.0f} us; the impact lasts"
                     f" {1e6 * w['duration']:.0f} us. The impulses of all contacts add up to"
                     f" {w['impulse_sum'] / w['delta_p']:.2e} delta_p, against"
                     f" {w['contact_updates']:.2e} contacts updated over the steps.")
    return lines


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--full", action="store_true", help="add the 100 x 100 packing")
    parser.add_argument("--reuse", action="store_true",
                        help="take the runs from docs/results/packings/scale.json")
    arguments = parser.parse_args()
    saved = os.path.join(OUT, "packings", "scale.json")
    if arguments.reuse:
        with open(saved) as stream:
            sizes = json.load(stream)
    else:
        sides = [16, 32, 56] + ([100] if arguments.full else [])
        sizes = [study(side) for side in sides]
        os.makedirs(os.path.join(OUT, "packings"), exist_ok=True)
        with open(saved, "w") as stream:
            json.dump(sizes, stream, indent=1)
    wakes = [wake(side) for side in (32, 56)]
    draw(sizes, wakes, os.path.join(OUT, "packings", "scale.png"))
    with open(os.path.join(OUT, "packing_scale.md"), "w") as stream:
        stream.write(report(sizes, wakes))


if __name__ == "__main__":
    main()
