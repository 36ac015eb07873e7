#!/usr/bin/python3
"""Runs the golden scenes with two `mimpact` binaries and compares every file they write.

The golden scenes are the example scenes (chains C1-C3 under every method and integrator, the
paper's scenes as they are, the 10 x 10 hexagonal packing) and the packing study's scenes at
sizes that run in seconds (hexagonal 16 x 16 and FCC 6^3 in the moving geometry, elastic and
inelastic; the frozen geometry; a square packing under LZB). A file is the same when it is
equal to the bit but for the measured wall time and the keys a later version adds to
summary.json; otherwise the script prints the largest
difference of its numbers, which must stay within 1e-12 of the striker's speed (1 m/s in every
golden scene) where operations were reordered.

    /usr/bin/python3 scripts/golden_compare.py OLD_MIMPACT NEW_MIMPACT [--keep DIR]

scripts/golden-compare.sh REV builds REV's binary and calls this script.
"""
import argparse
import copy
import json
import math
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "examples" / "scenes"
IGNORED_KEYS = {"wall_time"}  # s, measured
BOUND = 1e-12  # of the striker's speed (1 m/s), where operations were reordered


def load(path):
    text = Path(path).read_text()
    return json.loads(re.sub(r"^\s*//.*$", "", text, flags=re.M))


def chain_variants():
    """(name, command, scene) for the chains: every example chain under every method."""
    for chain in ("c1", "c2", "c3"):
        base = load(SCENES / f"{chain}.json")
        methods = {
            "impulse": {"impact": {"integrator": "impulse-step", "delta_p": 1e-5}},
            "adaptive": {"impact": {"integrator": "adaptive", "tolerance": 1e-8}},
            "asynchronous": {"impact": {"integrator": "asynchronous", "delta_p": 1e-5}},
            "compliant": {"method": "compliant", "compliant": {"tolerance": 1e-10}},
        }
        for method, change in methods.items():
            scene = copy.deepcopy(base)
            for key, value in change.items():
                scene[key] = {**scene.get(key, {}), **value} if isinstance(value, dict) else value
            if method == "adaptive":
                scene["impact"].pop("delta_p", None)
            yield f"{chain}_{method}", "chain", scene
    for path in sorted((SCENES / "paper").glob("*.json")):
        if path.name != "published.json":
            yield f"paper_{path.stem}", "chain", load(path)


def packing_scene(lattice, target, contact, method):
    planar = lattice["type"] in ("hexagonal", "square")
    return {"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
            "lattice": lattice,
            "strikers": [{"target": target, "radius": lattice["radius"],
                          "velocity": [0, 1] if planar else [0, 0, 1]}],
            "contact": contact, **method}


def packing_variants():
    """(name, command, scene) for the packings: the example and the study's scenes, smaller."""
    hexagon = load(SCENES / "packings" / "hexagonal_10x10.json")
    yield "hexagonal_10x10", "packing", hexagon
    lzb = {"impulse": {"integrator": "impulse-step", "delta_p": 1e-5},
           "asynchronous": {"integrator": "asynchronous", "delta_p": 1e-5}}
    for name, impact in lzb.items():
        scene = copy.deepcopy(hexagon)
        scene["impact"] = impact
        scene["configuration_check"] = {"enabled": False}
        yield f"hexagonal_10x10_{name}", "packing", scene
    frozen = copy.deepcopy(hexagon)
    frozen.update(method="compliant", compliant={"tolerance": 1e-8, "geometry": "frozen"})
    yield "hexagonal_10x10_frozen", "packing", frozen
    hexagonal = {"type": "hexagonal", "rows": 16, "columns": 16, "radius": 0.005}
    fcc = {"type": "fcc", "layers": 6, "rows": 6, "columns": 6, "radius": 0.005}
    square = {"type": "square", "rows": 8, "columns": 8, "radius": 0.005}
    for e in (1.0, 0.9):
        contact = {"model": "bi-stiffness", "exponent": 1.5, "restitution": e}
        for tolerance in (1e-4, 1e-8):
            moving = {"method": "compliant",
                      "compliant": {"tolerance": tolerance, "end_time": 5e-4}}
            yield (f"hexagonal_16x16_moving_e{e}_tol{tolerance:g}", "packing",
                   packing_scene(hexagonal, [0, 8], contact, moving))
            yield (f"fcc_6_moving_e{e}_tol{tolerance:g}", "packing",
                   packing_scene(fcc, [0, 3, 3], contact, {**moving, "compliant": {
                       "tolerance": tolerance, "end_time": 1.5e-4}}))
        adaptive = {"impact": {"integrator": "adaptive", "tolerance": 1e-6},
                    "configuration_check": {"enabled": False}}
        yield (f"hexagonal_16x16_adaptive_e{e}", "packing",
               packing_scene(hexagonal, [0, 8], contact, adaptive))
        yield (f"square_8x8_adaptive_e{e}", "packing",
               packing_scene(square, [0, 4], contact, {"impact": {
                   "integrator": "adaptive", "tolerance": 1e-8}}))


def run(binary, command, scene_path, out):
    result = subprocess.run([binary, command, str(scene_path), "--out", str(out), "--quiet"],
                            capture_output=True, text=True)
    (out / "stderr.txt").parent.mkdir(parents=True, exist_ok=True)
    (out / "stderr.txt").write_text(result.stderr)
    (out / "exit_code.txt").write_text(f"{result.returncode}\n")


def numbers(text):
    return [float(x) for x in re.findall(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|nan|inf",
                                          text)]


def strip_ignored(value):
    if isinstance(value, dict):
        return {k: strip_ignored(v) for k, v in value.items() if k not in IGNORED_KEYS}
    if isinstance(value, list):
        return [strip_ignored(v) for v in value]
    return value


def old_keys_only(old, new):
    """`new` without the keys `old` lacks: what a later version adds is not a change."""
    if isinstance(old, dict) and isinstance(new, dict):
        return {k: old_keys_only(old[k], v) for k, v in new.items() if k in old}
    if isinstance(old, list) and isinstance(new, list) and len(old) == len(new):
        return [old_keys_only(a, b) for a, b in zip(old, new)]
    return new


def difference(old_file, new_file):
    """None if the same but for wall time and added keys; else the largest difference of their
    numbers."""
    old, new = old_file.read_text(), new_file.read_text()
    if old_file.suffix == ".json":
        old_json = strip_ignored(json.loads(old))
        old = json.dumps(old_json)
        new = json.dumps(old_keys_only(old_json, strip_ignored(json.loads(new))))
    if old_file.name == "stderr.txt":  # the report's seconds of computation
        old, new = (re.sub(r"in [0-9.e+-]+ s of computation", "", t) for t in (old, new))
    if old == new:
        return None
    a, b = numbers(old), numbers(new)
    if len(a) != len(b):
        return math.inf
    return max((abs(x - y) for x, y in zip(a, b) if not (x == y)), default=0.0)


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("--keep", help="write the runs here instead of a scratch directory")
    args = parser.parse_args()
    work = Path(args.keep) if args.keep else Path(tempfile.mkdtemp(prefix="mimpact-golden-"))
    same = reordered = failed = 0
    for name, command, scene in [*chain_variants(), *packing_variants()]:
        scene_path = work / "scenes" / f"{name}.json"
        scene_path.parent.mkdir(parents=True, exist_ok=True)
        scene_path.write_text(json.dumps(scene, indent=1))
        for side, binary in (("old", args.old), ("new", args.new)):
            out = work / side / name
            shutil.rmtree(out, ignore_errors=True)
            out.mkdir(parents=True)
            run(binary, command, scene_path, out)
        old_files = sorted(p.name for p in (work / "old" / name).iterdir())
        new_files = sorted(p.name for p in (work / "new" / name).iterdir())
        if old_files != new_files:
            print(f"{name}: files differ: {old_files} against {new_files}")
            failed += 1
            continue
        worst = {f: difference(work / "old" / name / f, work / "new" / name / f)
                 for f in old_files}
        worst = {f: d for f, d in worst.items() if d is not None}
        if not worst:
            same += 1
            print(f"{name}: the same to the bit ({len(old_files)} files)")
        elif max(worst.values()) <= BOUND:
            reordered += 1
            print(f"{name}: within {max(worst.values()):.3g} ({', '.join(worst)})")
        else:
            failed += 1
            print(f"{name}: DIFFERS, largest {max(worst.values()):.3g} in "
                  + ", ".join(f"{f} {d:.3g}" for f, d in worst.items()))
    print(f"golden scenes: {same} the same to the bit, {reordered} within {BOUND:g} m/s, "
          f"{failed} differ")
    if not args.keep:
        shutil.rmtree(work)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
