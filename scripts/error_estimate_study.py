"""How a run's true error follows its step rule, and what a companion run tells of it (issue 48).

For each scene and step value k of a small corpus (chains and a planar packing; the impulse
steps' delta_p, the adaptive LZB's tolerance, the compliant method's tolerance in either
geometry), runs the scene at k, at r k (the companion: r = 2 for delta_p, 10 for a tolerance)
and at k / 1000 (the reference). Prints, relative to the fastest speed before the impact, the
true error of the run at k (RMS over bodies and worst body, against the reference), the
companion's difference from the run, their ratio, and the companion's wall time against the
run's. docs/design/error_estimates.md reads this table.

    PYTHONPATH=build/release/python /usr/bin/python3 scripts/error_estimate_study.py

About 3 minutes.
"""

import copy
import json
import math
import re
import time
from pathlib import Path

import numpy as np

import mimpact

SCENES = Path(__file__).resolve().parent.parent / "examples" / "scenes"


def load(name):
    text = (SCENES / name).read_text()
    return json.loads(re.sub(r"^\s*//.*$", "", text, flags=re.M))


def run(kind, scene):
    start = time.perf_counter()
    result = (mimpact.run_chain if kind == "chain" else mimpact.run_packing)(scene)
    velocity = np.asarray(result.summary["post_impact_velocities"], float)
    return velocity.reshape(len(velocity), -1), time.perf_counter() - start


def apart(a, b, speed):
    """RMS over bodies and worst body of |a - b|, relative to `speed`."""
    per_body = np.linalg.norm(a - b, axis=1) / speed
    return math.sqrt(float(np.mean(per_body ** 2))), float(per_body.max())


def at(scene, field, value):
    changed = copy.deepcopy(scene)
    group, key = field
    changed.setdefault(group, {})[key] = value
    return changed


def study(name, kind, scene, field, values, ratio):
    speed = 1.0  # every scene here is struck at 1 m/s
    for value in values:
        v, seconds = run(kind, at(scene, field, value))
        companion, companion_seconds = run(kind, at(scene, field, value * ratio))
        reference, _ = run(kind, at(scene, field, value / 1000))
        true, told = apart(v, reference, speed), apart(v, companion, speed)
        print(f"| {name} | {field[1]} {value:.0e} | {true[0]:.2e} | {true[1]:.2e} | "
              f"x{ratio}: {told[0]:.2e} | {told[0] / true[0]:.3g} | "
              f"{companion_seconds / seconds:.2f} |", flush=True)


def main():
    print("| scene | step | true RMS | true worst | companion RMS | ratio | companion cost |")
    print("|---|---|---|---|---|---|---|")
    c1 = load("c1.json")
    study("C1", "chain", c1, ("impact", "delta_p"), [1e-4, 1e-5, 1e-6], 2)
    for e in (1.0, 0.9, 0.5):
        adaptive = copy.deepcopy(c1)
        adaptive["contact"]["restitution"] = e
        adaptive["impact"] = {"integrator": "adaptive"}
        study(f"C1 e {e} adaptive", "chain", adaptive, ("impact", "tolerance"),
              [1e-4, 1e-6, 1e-8], 10)
        compliant = copy.deepcopy(adaptive)
        compliant.pop("impact")
        compliant["method"] = "compliant"
        study(f"C1 e {e} compliant", "chain", compliant, ("compliant", "tolerance"),
              [1e-5, 1e-7, 1e-9], 10)
    chain = copy.deepcopy(c1)
    chain["chain"]["segments"][0]["count"] = 1000
    chain["impact"] = {"integrator": "adaptive"}
    study("1000 beads adaptive", "chain", chain, ("impact", "tolerance"), [1e-5, 1e-7], 10)
    packing = load("packings/hexagonal_10x10.json")
    packing.pop("record")
    packing["configuration_check"] = {"enabled": False}
    study("hexagonal 10 x 10", "packing", packing, ("impact", "tolerance"), [1e-4, 1e-6, 1e-8], 10)
    packing["impact"] = {"delta_p": 1e-6}
    study("hexagonal 10 x 10", "packing", packing, ("impact", "delta_p"), [1e-5, 1e-6], 2)
    for e, geometry in ((1.0, "moving"), (0.5, "moving"), (1.0, "frozen")):
        compliant = copy.deepcopy(packing)
        compliant.pop("impact")
        compliant.pop("configuration_check")
        compliant["contact"]["restitution"] = e
        compliant["method"] = "compliant"
        compliant["compliant"] = {"geometry": geometry}
        values = [1e-4, 1e-6, 1e-8] if geometry == "moving" else [1e-5, 1e-7, 1e-9]
        study(f"hexagonal 10 x 10 e {e} compliant {geometry}", "packing", compliant,
              ("compliant", "tolerance"), values, 10)


if __name__ == "__main__":
    main()
