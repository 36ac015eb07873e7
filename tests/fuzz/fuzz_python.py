#!/usr/bin/env python3
"""Fuzzes the Python module: scene dicts with the values Python holds and JSON does not, the
kernel's classes with callables that return anything, observers that keep what they receive,
runs from two threads, and the helpers and studies with bad arguments.

Every case must end cleanly: a result whose numbers are finite, or ValueError (bad input),
TypeError (an argument of the wrong type, as Python's own functions raise it) or RuntimeError (a
run that failed) with a message of at most 1000 characters and none of a library's raw ones;
never a crash of the interpreter, a hang, or an object that reads garbage once its simulation
is gone. Each case runs in a worker process, which the fuzzer restarts when it dies; the cases
follow a seeded generator, so that --seed and --cases give the same inputs.

  PYTHONPATH=build/release/python python3 tests/fuzz/fuzz_python.py --seconds 60
"""
import argparse
import copy
import functools
import gc
import json
import math
import os
import random
import select
import subprocess
import sys
import threading
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent

# What a scene's values are replaced with: what JSON cannot hold, and the edges of what it can.
PYTHON_VALUES = [math.nan, math.inf, -math.inf, -0.0, 0, 2 ** 63, 2 ** 64, 10 ** 400, -(10 ** 400),
                 5e-324, 1e308, True, None, "", "x" * 100_000, b"bytes", (1, 2), [], {},
                 object(), 1e-170, -1, 1.5]


def numpy_values():
    import numpy as np
    return [np.float32(np.nan), np.int64(7), np.array([1.0, np.nan]), np.array(3.0),
            np.zeros((2, 2)), np.float64(1e-300)]


def deep(depth):
    top = current = {}
    for _ in range(depth):
        current["x"] = {}
        current = current["x"]
    return top


def mutate_scene(rng, scene):
    """One to three mutations of a scene dict, in place."""
    for _ in range(rng.randint(1, 3)):
        places = []

        def walk(node):
            items = node.items() if isinstance(node, dict) else enumerate(node)
            for key, value in list(items):
                places.append((node, key))
                if isinstance(value, (dict, list)):
                    walk(value)
        walk(scene)
        if not places:
            return scene
        container, key = rng.choice(places)
        action = rng.random()
        if action < 0.1 and isinstance(container, dict):
            del container[key]
        elif action < 0.2:
            container[key] = rng.choice([deep(rng.choice([10, 70, 100_000])), container])
        elif action < 0.3:
            container[key] = rng.choice(numpy_values())
        elif action < 0.4 and isinstance(container[key], (int, float)) and \
                not isinstance(container[key], bool):
            try:  # counts by 10 at most: more is a valid scene that runs for minutes
                power = rng.choice([-1, 1] if key in ("count", "rows", "columns") else
                                   [-3, -1, 1, 3])
                container[key] = container[key] * 10.0 ** power
            except OverflowError:  # an int beyond double precision, from an earlier mutation
                container[key] = rng.choice(PYTHON_VALUES)
        else:
            container[key] = rng.choice(PYTHON_VALUES)
    return scene


@functools.lru_cache(maxsize=None)
def seed_scenes():
    def load(path):
        text = "\n".join(line for line in path.read_text().splitlines()
                         if not line.lstrip().startswith("//"))
        return json.loads(text)
    return {"chain": [load(p) for p in sorted((HERE / "corpus" / "chain").glob("*.json"))],
            "packing": [load(p) for p in sorted((HERE / "corpus" / "packing").glob("*.json"))
                        if "beads" not in load(p)]}


# ------------------------------------------------------------------ checks of what comes back
class Failure(Exception):
    pass


class RaisedByCallable(Exception):
    """What a fuzzed callable raises: it must reach the caller unchanged (docs/python.md)."""


def raising(*_):
    raise RaisedByCallable("raised by the callable")


def finite(value, where):
    import numpy as np
    if isinstance(value, float) and not math.isfinite(value):
        raise Failure(f"non-finite output: {where} = {value}")
    if isinstance(value, np.ndarray) and value.dtype.kind == "f" and not np.all(np.isfinite(value)):
        raise Failure(f"non-finite output: {where} holds {value[~np.isfinite(value)][:3]}")
    if isinstance(value, dict):
        for key, item in value.items():
            finite(item, f"{where}.{key}")
    if isinstance(value, (list, tuple)):
        for index, item in enumerate(value):
            finite(item, f"{where}[{index}]")


def clean_error(error):
    """Raises Failure unless `error` is one a user may be given."""
    message = str(error)
    if isinstance(error, RaisedByCallable):
        return
    if not isinstance(error, (ValueError, TypeError, RuntimeError)):
        raise Failure(f"unclear error: {type(error).__name__}: {message[:200]}")
    for raw in ("json.exception", "Unable to cast", "basic_string", "std::"):
        if raw in message:
            raise Failure(f"a library's raw message: {message[:200]}")
    if len(message) > 1000:
        raise Failure(f"a message over 1000 characters: {message[:200]}")


# ------------------------------------------------------------------ the kinds of cases
# s a scene case may compute (max_seconds=): well inside the default --timeout of a case
MAX_SECONDS = 10.0


def scene_case(rng, mimpact):
    kind = rng.choice(["chain", "packing"])
    scene = mutate_scene(rng, copy.deepcopy(rng.choice(seed_scenes()[kind])))
    keywords = {}
    if rng.random() < 0.3:
        keywords["delta_p"] = rng.choice([1e-6, 0.0, -1.0, math.nan, math.inf, 1e-300, "x",
                                          2 ** 64])
    if rng.random() < 0.1:
        keywords["accuracy"] = rng.choice([1e-3, 1e-5, 0.0, math.nan, 1.0, -1e-4, "x"])
    if rng.random() < 0.05:
        keywords["estimate_error"] = False
    if rng.random() < 0.2 and "max_memory" in (mimpact.run_chain.__doc__ or ""):
        keywords["max_memory"] = rng.choice([0.5, 0.0, -1.0, math.nan, math.inf, 1e-9])
    if "max_seconds" in (mimpact.run_chain.__doc__ or ""):  # a long run ends cleanly there
        keywords["max_seconds"] = MAX_SECONDS
    run = mimpact.run_chain if kind == "chain" else mimpact.run_packing
    if kind == "chain" and rng.random() < 0.1:
        return mimpact.converge(scene, tolerance=rng.choice([[1e-3], [0.0], [math.nan], [1, 2, 3]]),
                                rows=rng.choice([1, 2, 0, -1]))
    if rng.random() < 0.1:
        return (mimpact.check_scene if kind == "chain" else run)(scene)
    result = run(scene, **keywords)
    finite(result.post_impact_velocities, "post_impact_velocities")
    finite(result.max_forces, "max_forces")
    finite(result.summary, "summary")
    return result


def junk(rng, size):
    import numpy as np
    return rng.choice([[0.0] * size, [math.nan] * size, None, "down", [1.0] * (size + 1),
                       np.full(size, np.inf), [[0.0] * size], lambda: 0, [1e308] * size,
                       [-9.81] * size])


def kernel_case(rng, mimpact):
    """A ball on a floor with random data and callables; observers keep what they receive and
    read it after the simulation is gone."""
    mass = rng.choice([[[1.0]], [[math.nan]], [[-1.0]], [[1.0, 0.0]], [[0.0]], [[1e-300]]])
    start = rng.choice([[1.0], [math.nan], [1e308], [0.0]])
    forces = {}
    if rng.random() < 0.5:
        result = junk(rng, 1)
        forces["external_force"] = (lambda t: result) if rng.random() < 0.8 else raising
    if rng.random() < 0.2:
        forces["mass"] = lambda q: junk(rng, 1)
    ball = mimpact.LagrangianDS(start, [0.0], forces.pop("mass", mass), name="ball", **forces)
    system = mimpact.NonSmoothDynamicalSystem()
    system.add(ball)
    system.add(mimpact.Interaction(ball, mimpact.LinearRelation([1.0], 0.0),
                                   mimpact.LzbLaw(stiffness=rng.choice([1e8, 1e300, 1e-300]),
                                                  restitution=rng.choice([0.8, 0.0, 1e-300]),
                                                  exponent=rng.choice([1.5, 1.0, 10.0])),
                                   "floor"))
    options = rng.choice([{"relative_delta_p": 1e-3}, {"integrator": "adaptive"},
                          {"integrator": "adaptive", "delta_p": 1e-5}, {"relative_delta_p": 2.0},
                          {"delta_p": 1e-5, "relative_delta_p": 1e-3}, {"tolerance": math.nan}])
    simulation = mimpact.Simulation(system, impact_options=options)
    kept, seen = [], []

    def on_impact(state, impact):
        kept.append((state, impact, impact.velocity_after))
        seen.append((impact.time, impact.velocity_after.tolist()))

    simulation.add_observer(on_impact=on_impact,
                            on_step=lambda state, step: kept.append(step) or
                            rng.choice([None, None, None, "stop", 42]))
    end = rng.choice([1.0, math.inf, -1.0, math.nan, 0.0])
    if rng.random() < 0.1:  # a second run from another thread
        other = threading.Thread(target=lambda: _quiet(simulation.run, 0.0, end))
        other.start()
        _quiet(simulation.run, 0.0, end)
        other.join()
    else:
        simulation.run(0.0, end)
    del simulation, system
    gc.collect()
    for (state, impact, velocity), (when, speeds) in zip(
            [k for k in kept if isinstance(k, tuple)], seen):
        if impact.time != when or velocity.tolist() != speeds:
            raise Failure("garbage: a kept ImpactReport changed after the run")
        finite(state.system.system(0).position, "kept state")
    finite(ball.position, "position")


def _quiet(run, *arguments):
    try:
        run(*arguments)
    except (ValueError, RuntimeError):
        pass


def helper_case(rng, mimpact):
    steel = {"density": 7780, "young": 203e9, "poisson": 0.3}
    radius = rng.choice([0.01, -1.0, math.nan, math.inf, 0.0, 1e200, 1e-300])
    material = mutate_scene(rng, copy.deepcopy({"material": steel}))
    material = material.get("material", steel)
    value = rng.choice([mimpact.bead_mass, mimpact.hertz_stiffness_wall,
                        lambda r, m: mimpact.hertz_stiffness(r, m, 0.01, steel)])(
        radius, material if isinstance(material, dict) else steel)
    finite(value, "helper")
    if rng.random() < 0.3:
        grid = rng.choice([{"strikers.0.velocity": [0.5, math.nan]}, {"contact.restitution": []},
                           {"nothing.here": [1]}, {}, [], {"strikers.0.velocity": [0.5, 2.0]}])
        for result in mimpact.sweep(seed_scenes()["chain"][0], grid,
                                    workers=rng.choice([1, 2, 0, -1, "x"])):
            finite(result.post_impact_velocities, "sweep")


def run_case(seed, index):
    """One case, in this process; returns None or the failure's text."""
    import mimpact
    rng = random.Random(seed * 1_000_003 + index)
    case = rng.choice([scene_case, scene_case, kernel_case, helper_case])
    try:
        case(rng, mimpact)
    except Failure as failure:
        return str(failure)
    except Exception as error:  # noqa: BLE001 - judged by clean_error
        try:
            clean_error(error)
        except Failure as failure:
            return f"{case.__name__}: {failure}"
    return None


# ------------------------------------------------------------------ workers
WORKER = """
import json, sys
sys.path.insert(0, {here!r})
import fuzz_python
for line in sys.stdin:
    seed, index = json.loads(line)
    print(json.dumps(fuzz_python.run_case(seed, index)), flush=True)
"""


class Worker:
    def __init__(self):
        self.process = subprocess.Popen([sys.executable, "-c", WORKER.format(here=str(HERE))],
                                        stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                        stderr=subprocess.DEVNULL, text=True)

    def run(self, seed, index, timeout):
        self.process.stdin.write(json.dumps([seed, index]) + "\n")
        self.process.stdin.flush()
        ready, _, _ = select.select([self.process.stdout], [], [], timeout)
        if not ready:
            self.process.kill()
            self.process.wait()
            return f"run past its limit: no answer after {timeout:g} s"
        line = self.process.stdout.readline()
        if not line:
            code = self.process.wait()
            return f"crash: the interpreter ended with status {code}"
        return json.loads(line)

    def alive(self):
        return self.process.poll() is None

    def close(self):
        if self.alive():
            self.process.stdin.close()
            self.process.wait()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--cases", type=int, default=0, help="cases (0: until --seconds)")
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument("--timeout", type=float, default=30.0, help="s a case may run")
    arguments = parser.parse_args()
    counts = {}
    worker = Worker()
    start = time.monotonic()
    index = 0
    while (index < arguments.cases if arguments.cases else
           time.monotonic() - start < arguments.seconds):
        index += 1
        failure = worker.run(arguments.seed, index, arguments.timeout)
        if failure:
            kind = failure.split(":")[0] if not failure.startswith(("scene_case", "kernel_case",
                                                                    "helper_case")) \
                else failure.split(":")[1].strip()
            counts[kind] = counts.get(kind, 0) + 1
            print(f"FAIL case {arguments.seed}:{index}: {failure[:300]}", flush=True)
        if not worker.alive():
            worker = Worker()
    worker.close()
    failed = sum(counts.values())
    print(f"{index} cases (seed {arguments.seed}) in {time.monotonic() - start:.0f} s, "
          f"{failed} failed")
    for kind, count in sorted(counts.items()):
        print(f"  {count:5d}  {kind}")
    print(f"replay one: python3 -c 'import sys; sys.path.insert(0, \"{HERE}\"); import "
          f"fuzz_python; print(fuzz_python.run_case(SEED, INDEX))'")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
