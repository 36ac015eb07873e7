"""run_chain() and converge(): the chains of the command line, from Python."""

import copy
import json
import re
import subprocess
import threading

import numpy as np
import pytest

import mimpact
from conftest import SOURCE


def adaptive(scene, tolerance):
    scene = copy.deepcopy(scene)
    scene["impact"] = {"integrator": "adaptive", "tolerance": tolerance}
    return scene


def test_same_numbers_as_the_command_line(c1, cli, tmp_path):
    """The module and `mimpact chain` run the same code: the same velocities, to the bit."""
    path = SOURCE / "examples/scenes/c1.json"
    result = mimpact.run_chain(path)
    subprocess.run([cli, "chain", str(path), "--out", str(tmp_path), "--quiet"], check=True)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert result.status == "terminated"
    assert result.delta_p == c1["impact"]["delta_p"]
    np.testing.assert_array_equal(result.post_impact_velocities, summary["post_impact_velocities"])
    assert result.steps == summary["impulse_steps"]
    assert result.summary["momentum"] == summary["momentum"]


def test_adaptive_lzb_meets_the_hertz_chain(c1):
    """C1 (e = 1): the adaptive LZB at 1e-10 and the compliant Hertz chain, two independent
    integrations of the same elastic dynamics, agree to 1e-8 (docs/model.md, section 10)."""
    lzb = mimpact.run_chain(adaptive(c1, 1e-10))
    hertz = dict(c1, method="compliant", compliant={"tolerance": 1e-12})
    del hertz["impact"]
    reference = mimpact.run_chain(hertz)
    v, v_ref = lzb.post_impact_velocities, reference.post_impact_velocities
    assert np.linalg.norm(v - v_ref) / np.linalg.norm(v_ref) < 1e-8
    assert lzb.delta_p is None


def test_momentum_is_kept_and_arrays_have_their_sizes(c1):
    result = mimpact.run_chain(c1, delta_p=1e-4 * 0.0326)
    beads = c1["chain"]["segments"][0]["count"]
    assert result.post_impact_velocities.shape == (beads + 1,)
    for array in (result.impulses, result.max_forces, result.times_of_max_force):
        assert array.shape == (beads,)
    momentum = result.summary["momentum"]
    assert momentum["after"] == pytest.approx(momentum["before"], rel=1e-12)
    assert np.all(result.max_forces > 0) and np.all(np.diff(result.times_of_max_force) > 0)


def test_recorded_series_as_arrays(c1):
    scene = adaptive(c1, 1e-8)
    scene["record"] = {"contacts": [0, 10], "bodies": [20], "interval": 1e-7}
    result = mimpact.run_chain(scene)
    series = result.series
    assert series["contacts"] == [0, 10] and series["bodies"] == [20]
    samples = series["time"].size
    assert samples > 100
    assert series["forces"].shape == (samples, 2)
    assert series["velocities"].shape == (samples, 1)
    # the sampled force peaks just below the exact largest force (0.1 us between samples)
    peaks = series["forces"].max(axis=0)
    np.testing.assert_allclose(peaks, result.max_forces[[0, 10]], rtol=1e-2)
    assert np.all(peaks <= result.max_forces[[0, 10]] * (1 + 1e-12))
    # the last bead leaves with the post-impact velocity
    assert series["velocities"][-1, 0] == pytest.approx(result.post_impact_velocities[20], rel=1e-6)


def test_converge_tightens_until_the_velocities_settle(c1):
    study = mimpact.converge(adaptive(c1, 1e-3), tolerance=[1e-6])
    assert study["study"] == "tolerance" and study["converged"]
    changes = [row["eta_plus"] for row in study["rows"]]
    assert all(later < earlier for earlier, later in zip(changes, changes[1:]))
    assert changes[-1] <= 1e-6


def test_the_computation_lets_other_python_threads_run(c1):
    """The GIL is released while C++ computes: a Python loop keeps running beside a long run."""
    done = threading.Event()
    thread = threading.Thread(
        target=lambda: (mimpact.run_chain(c1, delta_p=2e-7), done.set()))
    thread.start()
    turns = 0
    while not done.is_set():
        turns += 1
    thread.join()
    assert turns > 10_000


@pytest.mark.parametrize(
    "change, named",
    [
        (lambda s: s["contact"].update(restitution=1.5), "contact.restitution"),
        (lambda s: s["strikers"][0].update(velocity="fast"), "strikers[0].velocity = \"fast\" (a string) is invalid; allowed: a number, >= 1e-100"),
        (lambda s: s.update(colour="red"), "colour"),
        (lambda s: s["chain"]["segments"][0].update(count=0), "count"),
        (lambda s: s["strikers"][0].update(velocity=object()), "scene.strikers[0].velocity = <object"),
    ],
)
def test_bad_scene_raises_value_error_naming_the_field(c1, change, named):
    change(c1)
    with pytest.raises(ValueError, match=re.escape(named)):
        mimpact.run_chain(c1)


def test_bad_arguments_raise_value_error(c1):
    with pytest.raises(ValueError, match="delta_p"):
        mimpact.run_chain(c1, delta_p=-1.0)
    with pytest.raises(ValueError, match="scene file's path or a dict"):
        mimpact.run_chain(42)
    with pytest.raises(ValueError, match="rows"):
        mimpact.converge(c1, rows=0)
    with pytest.raises(ValueError, match="no such file|cannot|open"):
        mimpact.run_chain("no/such/scene.json")


@pytest.mark.parametrize("method", ["impulse steps", "adaptive", "compliant"])
def test_energy_ledger_balances(method):
    """kinetic_before (+ a precompression's potential and work) = kinetic_after + dissipated +
    potential_left, to round-off; C3's contacts (e = 0.6) dissipate, none negatively."""
    from conftest import read_scene

    scene = read_scene("examples/scenes/c3.json")
    if method == "adaptive":
        scene["impact"] = {"integrator": "adaptive", "tolerance": 1e-8}
    elif method == "compliant":
        del scene["impact"]
        scene["method"] = "compliant"
    result = mimpact.run_chain(scene)
    energy = result.energy
    before = energy["kinetic_before"] + energy["potential_before"] + energy["work_of_forces"]
    after = energy["kinetic_after"] + energy["dissipated_total"] + energy["potential_left"]
    # round-off: at most a machine epsilon of the energy per step
    assert after == pytest.approx(before, rel=max(result.steps, 100) * np.finfo(float).eps)
    assert isinstance(energy["dissipated"], np.ndarray) and energy["dissipated"].shape == (20,)
    assert energy["dissipated"].sum() == pytest.approx(energy["dissipated_total"], rel=1e-12)
    assert energy["dissipated"].min() >= -1e-12 * energy["kinetic_before"]
    assert energy["dissipated_total"] > 0.1 * energy["kinetic_before"]
