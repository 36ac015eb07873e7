"""Parameter sweeps: one run_chain() per point of a grid, in parallel on the local cores or on
a Dask distributed cluster."""

import concurrent.futures
import itertools
import os

from ._mimpact import check_scene, run_chain
from .scene_paths import scene_dict, set_path


def grid_points(grid):
    """The points of the grid's Cartesian product, in its order (the first path varying
    slowest), each a dict from dotted path to value."""
    if not isinstance(grid, dict) or not grid:
        raise ValueError(f"grid = {grid!r} is not allowed; allowed: a non-empty dict from dotted "
                         "paths of the scene to lists of values")
    values = []
    for path, choices in grid.items():
        if isinstance(choices, (str, bytes, dict)) or not hasattr(choices, "__iter__"):
            raise ValueError(f"grid[{path!r}] = {choices!r} is not allowed; allowed: a list of "
                             "values")
        choices = list(choices)
        if not choices:
            raise ValueError(f"grid[{path!r}] is empty; allowed: a non-empty list of values")
        values.append(choices)
    return [dict(zip(grid, point)) for point in itertools.product(*values)]


def scenes_of(scene, points):
    """The scene with each point's values set, each checked as run_chain() would check it."""
    base = scene_dict(scene)
    scenes = []
    for point in points:
        changed = scene_dict(base)
        for path, value in point.items():
            set_path(changed, path, _plain(value))
        try:
            check_scene(changed)
        except ValueError as error:
            raise ValueError(f"at {point}: {error}") from None
        scenes.append(changed)
    return scenes


def _plain(value):
    """NumPy numbers and arrays as Python's, for the scene's JSON."""
    return value.tolist() if hasattr(value, "tolist") and hasattr(value, "dtype") else value


def _run(scene):
    """run_chain() as a Python function: pickled by reference for Dask's workers, which import
    mimpact themselves (a compiled function cannot be pickled). One thread a point: the sweep
    fills the cores with points, so each run's error estimate follows it rather than beside."""
    return run_chain(scene, threads=1)


def run_many(scenes, client=None, workers=None):
    """run_chain() on every scene, in order: on the Dask client's cluster when one is given,
    else on `workers` threads (default: the local cores; the computation releases the GIL)."""
    if client is not None:
        futures = client.map(_run, scenes, pure=False)
        return client.gather(futures)
    if workers is not None and (not isinstance(workers, int) or workers < 1):
        raise ValueError(f"workers = {workers!r} is not allowed; allowed: an integer >= 1")
    with concurrent.futures.ThreadPoolExecutor(max_workers=workers or os.cpu_count()) as pool:
        return list(pool.map(_run, scenes))


def sweep(scene, grid, client=None, workers=None):
    """One run_chain() result per point of the Cartesian product of `grid`, in the grid's order
    (the first path varying slowest; grid_points(grid) lists the points).

    scene: a scene file's path or a dict with its keys. grid: {dotted path: values}, e.g.
    {"contact.restitution": [0.9, 0.95], "strikers.0.velocity": [0.5, 1.0]}. client: a
    dask.distributed.Client to run the points on its cluster; by default they run on the local
    cores. Every point is checked before any runs: bad input raises ValueError naming the point.
    """
    points = grid_points(grid)
    return run_many(scenes_of(scene, points), client=client, workers=workers)
