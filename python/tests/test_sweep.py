"""sweep(): one run_chain() per grid point, in the grid's order, locally or on Dask."""

import re

import numpy as np
import pytest

import mimpact
from conftest import SOURCE

# Debian's tornado warns of its own API under distributed 2022.12
pytestmark = pytest.mark.filterwarnings("ignore:make_current is deprecated:DeprecationWarning")

NAKAGAWA = SOURCE / "examples/scenes/paper/nakagawa_e0955.json"


def adaptive(scene):
    scene = mimpact.read_scene(scene)
    scene.pop("record", None)
    scene["impact"] = {"integrator": "adaptive", "tolerance": 1e-6}
    return scene


def test_points_in_the_grids_order_and_each_run_as_alone():
    grid = {"contact.restitution": [0.9, 1.0], "strikers.0.velocity": [0.5, 1.0, 2.0]}
    points = mimpact.grid_points(grid)
    assert points[:4] == [
        {"contact.restitution": 0.9, "strikers.0.velocity": 0.5},
        {"contact.restitution": 0.9, "strikers.0.velocity": 1.0},
        {"contact.restitution": 0.9, "strikers.0.velocity": 2.0},
        {"contact.restitution": 1.0, "strikers.0.velocity": 0.5},
    ]
    scene = adaptive(SOURCE / "examples/scenes/c1.json")
    results = mimpact.sweep(scene, grid)
    assert len(results) == 6
    for point, result in zip(points, results):
        alone = dict(scene, contact=dict(scene["contact"], restitution=point["contact.restitution"]))
        alone["strikers"] = [dict(scene["strikers"][0], velocity=point["strikers.0.velocity"])]
        np.testing.assert_array_equal(result.post_impact_velocities,
                                      mimpact.run_chain(alone).post_impact_velocities)
    # an elastic chain's outcome scales with the striker's speed: momentum and energy kept
    elastic = results[3:]
    for result, speed in zip(elastic, [0.5, 1.0, 2.0]):
        assert result.energy["kinetic_after"] == pytest.approx(
            result.energy["kinetic_before"], rel=1e-5)
        assert result.summary["momentum"]["after"] == pytest.approx(
            result.summary["momentum"]["before"], rel=1e-12)


def test_a_dask_cluster_gives_the_serial_sweep():
    distributed = pytest.importorskip("distributed")
    grid = {"contact.restitution": [0.9, 0.955], "chain.segments.0.taper": [0.0, 0.05, 0.1]}
    scene = adaptive(NAKAGAWA)
    serial = mimpact.sweep(scene, grid, workers=1)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        on_cluster = mimpact.sweep(scene, grid, client=client)
    assert len(on_cluster) == len(serial) == 6
    for a, b in zip(on_cluster, serial):
        np.testing.assert_array_equal(a.post_impact_velocities, b.post_impact_velocities)
        np.testing.assert_array_equal(a.max_forces, b.max_forces)
        assert a.energy["dissipated_total"] == b.energy["dissipated_total"]


@pytest.mark.parametrize(
    "grid, message",
    [
        ({"contact.restitutio": [0.9]}, "restitutio"),
        ({"strikers.3.velocity": [1.0]}, "strikers has 1 entries; index 3 is not allowed"),
        ({"contact.restitution": ["high"]}, 'contact.restitution = "high" (a string) is invalid'),
        ({"contact.restitution": [1.5]}, "contact.restitution = 1.5 is invalid"),
        ({"contact.restitution": []}, "is empty"),
        ({"contact.restitution": 0.9}, "allowed: a list of values"),
        ({}, "non-empty dict"),
        ({"contact..restitution": [0.9]}, "joined by dots"),
    ],
)
def test_bad_grids_are_named_before_anything_runs(grid, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        mimpact.sweep(SOURCE / "examples/scenes/c1.json", grid)
