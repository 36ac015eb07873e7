"""Every run reports its own error, and `accuracy` is the one knob (issue 48), from Python and
from the command line: the estimate on by default, the accuracy met against a run far finer, and
the accuracy alone with the step rule it chooses."""

import copy
import json
import subprocess

import numpy as np
import pytest

import mimpact

from test_bounded_runs import run_cli, square_on_a_wall


def test_every_run_reports_its_error_unless_told_not_to(c1, cli, tmp_path):
    result = mimpact.run_chain(c1)
    estimate = result.error_estimate
    assert set(estimate) == {"rms", "worst", "method", "companion_seconds"}
    assert 0 < estimate["rms"] <= estimate["worst"] < 1e-2
    assert "2 x the delta_p" in estimate["method"] and result.accuracy is None
    assert mimpact.run_chain(c1, estimate_error=False).error_estimate is None
    done, summary = run_cli(cli, "chain", c1, tmp_path)
    assert summary["error_estimate"]["worst"] == estimate["worst"]  # the same runs
    done, summary = run_cli(cli, "chain", c1, tmp_path, "--no-error-estimate")
    assert "error_estimate" not in summary
    loud = subprocess.run([cli, "chain", str(tmp_path / "scene.json")], capture_output=True,
                          text=True, timeout=60)
    assert "error estimate: worst body" in loud.stderr


@pytest.mark.parametrize("how", [{"integrator": "impulse-step"}, {"integrator": "adaptive"}])
def test_an_lzb_run_meets_the_accuracy_asked_for(c1, how):
    c1["impact"] = how
    result = mimpact.run_chain(c1, accuracy=1e-5)
    assert result.accuracy["met"] and result.error_estimate["worst"] <= 1e-5
    # the truth: the continuous limit at a tolerance far below the accuracy
    exact = mimpact.run_chain(dict(c1, impact={"integrator": "adaptive", "tolerance": 1e-12}),
                              estimate_error=False)
    worst = np.max(np.abs(result.post_impact_velocities - exact.post_impact_velocities))
    assert worst <= 1e-5  # of the striker's 1 m/s
    step = "delta_p" if how["integrator"] == "impulse-step" else "tolerance"
    assert step in result.accuracy and result.summary[step] == result.accuracy[step] \
        if step == "tolerance" else result.delta_p == result.accuracy["delta_p"]


def test_a_budget_spent_ends_the_runs_not_met_and_says_why(c1, cli, tmp_path):
    # C1 at e = 0.5 meets 1e-10 at a tolerance of about 2e-12 (21 632 steps); with 15 000 steps
    # allowed, the answer is the first pair's run at 1e-10, its estimate above the accuracy
    c1.update(method="compliant", compliant={"max_steps": 15000}, accuracy=1e-10)
    c1["contact"]["restitution"] = 0.5
    del c1["impact"]
    result = mimpact.run_chain(c1)
    assert not result.accuracy["met"] and result.error_estimate["worst"] > 1e-10
    assert "spent its budget of steps" in result.accuracy["ended"]
    assert "max_steps = 15000" in result.accuracy["ended"]
    alone = mimpact.run_chain(dict(c1, accuracy=None, compliant={"max_steps": 15000,
                                                                 "tolerance": 1e-10}))
    assert np.array_equal(result.post_impact_velocities, alone.post_impact_velocities)
    done, summary = run_cli(cli, "chain", c1, tmp_path)
    assert summary["accuracy"] == result.accuracy
    loud = subprocess.run([cli, "chain", str(tmp_path / "scene.json")], capture_output=True,
                          text=True, timeout=60)
    assert "accuracy 1e-10 NOT met in 4 runs, tolerance 1e-10: a run finer" in loud.stderr


def test_a_packing_meets_the_accuracy_in_the_moving_geometry(cli, tmp_path):
    scene = square_on_a_wall([0.0, 1.0])
    scene.update(method="compliant", accuracy=1e-4, compliant={"end_time": 2e-4})
    del scene["impact"]
    result = mimpact.run_packing(scene)
    assert result.accuracy["met"] and result.error_estimate["worst"] <= 1e-4
    exact = mimpact.run_packing(dict(scene, accuracy=None, compliant={
        "end_time": 2e-4, "tolerance": result.accuracy["tolerance"] / 1000}), estimate_error=False)
    assert np.max(np.abs(result.post_impact_velocities - exact.post_impact_velocities)) <= 1e-4
    done, summary = run_cli(cli, "packing", scene, tmp_path)
    assert summary["accuracy"] == result.accuracy and summary["tolerance"] == \
        result.accuracy["tolerance"]


def test_the_accuracy_is_alone_with_its_step_rule(c1, cli, tmp_path):
    with pytest.raises(ValueError, match=r"delta_p = 1e-06 beside accuracy = 1e-05"):
        mimpact.run_chain(c1, accuracy=1e-5, delta_p=1e-6)
    for bad in (0.0, 0.5, float("nan")):
        with pytest.raises(ValueError, match=r"accuracy = .* allowed: 1e-12 <= accuracy <= 0.1"):
            mimpact.run_chain(c1, accuracy=bad)
    in_file = dict(copy.deepcopy(c1), accuracy=1e-5)
    in_file["impact"] = {"delta_p": 1e-6}
    with pytest.raises(ValueError, match=r"impact.delta_p = 1e-06 beside accuracy = 1e-05"):
        mimpact.run_chain(in_file)
    for arguments, message in ((["--accuracy", "1e-5", "--delta-p", "1e-6"],
                                "--delta-p = 1e-06 beside --accuracy = 1e-05"),
                               (["--accuracy", "2"], "--accuracy = 2 is invalid"),
                               (["--accuracy", "1e-5", "--tolerance", "1e-5"],
                                "--tolerance beside accuracy")):
        done, summary = run_cli(cli, "chain", c1, tmp_path, *arguments)
        assert done.returncode != 0 and message in done.stderr and summary is None
        assert not (tmp_path / "out").exists()
    # the command line's accuracy stands over the file's step rule, and its delta_p over the
    # file's accuracy
    done, summary = run_cli(cli, "chain", dict(in_file, accuracy=None), tmp_path, "--accuracy",
                            "1e-4")
    assert summary["accuracy"]["asked"] == 1e-4 and summary["integrator"] == "adaptive"
    del in_file["impact"]
    done, summary = run_cli(cli, "chain", in_file, tmp_path, "--delta-p", "1e-6")
    assert "accuracy" not in summary and summary["delta_p"] == 1e-6


def test_an_accuracy_beyond_the_step_budget_is_refused_after_a_cheap_pair(c1):
    c1["impact"] = {"integrator": "impulse-step"}
    with pytest.raises(ValueError, match=r"accuracy = 1e-09 needs delta_p of about .* impulse "
                                         r"steps, more than impact.max_steps = 1000000000"):
        mimpact.run_chain(c1, accuracy=1e-9)


def test_method_auto_decides_and_says_why(cli, tmp_path):
    import warnings
    hexagonal = {"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
                 "lattice": {"type": "hexagonal", "rows": 8, "columns": 8, "radius": 0.005},
                 "strikers": [{"target": [7, 3], "radius": 0.005, "velocity": [0, -1]}],
                 "contact": {"restitution": 0.9}, "compliant": {"end_time": 5e-4},
                 "method": "auto"}
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the method chosen is the right one: no warning
        result = mimpact.run_packing(hexagonal)
    assert result.summary["method"] == "compliant" and result.accuracy["asked"] == 1e-3
    assert "beyond the accuracy 0.001" in result.summary["method_choice"]
    # 6 x 6 as in test_method_auto: an 8 x 8 one at e = 0.9 parts from the beads as they move by
    # 1.2e-3 at worst, beyond 1e-3
    square = dict(hexagonal, lattice=dict(hexagonal["lattice"], type="square", rows=6, columns=6),
                  strikers=[dict(hexagonal["strikers"][0], target=[5, 2])])
    (tmp_path / "scene.json").write_text(json.dumps(square))
    done = subprocess.run([cli, "packing", str(tmp_path / "scene.json")], capture_output=True,
                          text=True, timeout=60)
    summary = json.loads(done.stdout)
    assert summary["method"] == "lzb" and "method auto: LZB: the beads as they move" in done.stderr
    assert "warning" not in done.stderr
