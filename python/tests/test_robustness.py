"""Every input from Python ends cleanly (issue 22, items 1, 3 and 5): what callbacks receive
outlives the simulation, one run at a time, no NaN in or out, nested and self-containing dicts
refused, every field named where it was given."""

import copy
import gc
import math
import threading

import numpy as np
import pytest

import mimpact

STEEL = {"density": 7780, "young": 203e9, "poisson": 0.3}


def falling_ball(**forces):
    """A ball of 1 kg dropped from 1 m on a floor (e = 0.8), its weight a Python callable."""
    ball = mimpact.LagrangianLinearTIDS([1.0], [0.0], [[1.0]], external_force=[-9.81],
                                        name="ball") if not forces else \
        mimpact.LagrangianDS([1.0], [0.0], [[1.0]], name="ball", **forces)
    system = mimpact.NonSmoothDynamicalSystem()
    system.add(ball)
    system.add(mimpact.Interaction(ball, mimpact.LinearRelation([1.0], 0.0),
                                   mimpact.LzbLaw(stiffness=1e8, restitution=0.8), "floor"))
    return ball, system


def test_what_observers_keep_outlives_the_simulation():
    _, system = falling_ball()
    simulation = mimpact.Simulation(system, impact_options={"relative_delta_p": 1e-3})
    kept = []
    seen = []

    def on_impact(state, impact):
        kept.append((state, impact, state.system.system(0).position, impact.velocity_after))
        seen.append((impact.time, float(impact.velocity_after[0]),
                     float(state.system.system(0).position[0])))

    def on_step(state, step):
        kept.append((state, step))

    simulation.add_observer(on_impact=on_impact, on_step=on_step)
    simulation.run(0.0, 2.0)
    del simulation, system
    gc.collect()
    impacts = [entry for entry in kept if len(entry) == 4]
    assert len(impacts) >= 2
    for (state, impact, position, velocity), (time, speed, height) in zip(impacts, seen):
        # the reports are copies: as they were when received, not garbage (it read 3.3e-315)
        assert impact.time == time and float(velocity[0]) == speed
        assert float(position[0]) == height
        # the simulation a callback kept is alive and whole after `del`
        assert state.time == pytest.approx(2.0)
        assert state.system.system(0).position.shape == (1,)
    assert all(step.time >= 0.0 for _, step in (e for e in kept if len(e) == 2))


def test_a_running_simulation_refuses_a_second_run():
    _, system = falling_ball()
    simulation = mimpact.Simulation(system, impact_options={"relative_delta_p": 1e-4})
    started = threading.Event()
    release = threading.Event()

    def on_start(state):
        started.set()
        release.wait(10)

    simulation.add_observer(on_start=on_start)
    errors = []

    def first():
        try:
            simulation.run(0.0, 0.5)
        except Exception as error:  # noqa: BLE001 - reported below
            errors.append(error)

    worker = threading.Thread(target=first)
    worker.start()
    assert started.wait(10)
    with pytest.raises(RuntimeError, match="already running"):
        simulation.run(0.0, 0.5)
    with pytest.raises(RuntimeError, match="while the simulation runs"):
        simulation.add_observer(on_step=lambda state, step: None)
    release.set()
    worker.join()
    assert not errors
    assert simulation.time == pytest.approx(0.5)


@pytest.mark.parametrize("returned, named", [
    (lambda t: [math.nan], "external_force(t) returned [nan], not finite"),
    (lambda t: None, "external_force(t) returned None, not finite"),
    (lambda t: "down", "external_force(t) returned 'down'"),
    (lambda t: [1.0, 2.0], "external_force(t) returned 2 values"),
])
def test_bad_values_from_a_callable_stop_the_run_naming_it(returned, named):
    _, system = falling_ball(external_force=returned)
    simulation = mimpact.Simulation(system, impact_options={"relative_delta_p": 1e-3})
    with pytest.raises(ValueError, match="system 'ball': " + named.replace("[", r"\[")
                       .replace("(", r"\(").replace(")", r"\)")):
        simulation.run(0.0, 1.0)


def test_setters_and_helpers_refuse_what_the_scene_reader_refuses():
    ball, system = falling_ball()
    simulation = mimpact.Simulation(system, impact_options={"relative_delta_p": 1e-3})
    with pytest.raises(ValueError, match="end time = inf is invalid"):
        simulation.run(0.0, math.inf)
    with pytest.raises(ValueError, match="start time = nan is invalid"):
        simulation.run(math.nan, 1.0)
    with pytest.raises(ValueError, match="NaN or infinite"):
        ball.set_state([math.nan], [0.0])
    assert ball.position[0] == 1.0  # unchanged
    with pytest.raises(ValueError, match="radius = -1 is invalid; allowed: > 0"):
        mimpact.bead_mass(-1, STEEL)
    with pytest.raises(ValueError, match="radius_b = nan is invalid"):
        mimpact.hertz_stiffness(0.01, STEEL, math.nan, STEEL)
    with pytest.raises(ValueError, match="bead_mass = inf leaves double precision"):
        mimpact.bead_mass(1e200, STEEL)
    with pytest.raises(ValueError, match="material: density = -1 is invalid"):
        mimpact.bead_mass(0.01, dict(STEEL, density=-1))
    with pytest.raises(ValueError, match="output interval"):
        simulation.schedule_outputs(0.0, 1e-30, 1.0)


def test_dicts_nested_too_deep_or_containing_themselves_are_refused(c1):
    deep = current = {}
    for _ in range(100_000):
        current["x"] = {}
        current = current["x"]
    scene = dict(c1, contact=deep)
    with pytest.raises(ValueError, match="nests dicts and lists deeper than 64 levels"):
        mimpact.run_chain(scene)
    looped = dict(c1)
    looped["impact"] = looped
    with pytest.raises(ValueError, match="or contains itself"):
        mimpact.run_chain(looped)


def test_numbers_python_holds_and_json_does_not_are_named(c1):
    scene = copy.deepcopy(c1)
    scene["strikers"][0]["velocity"] = math.nan
    with pytest.raises(ValueError, match=r"strikers\[0\]\.velocity = nan is invalid"):
        mimpact.run_chain(scene)
    scene["strikers"][0]["velocity"] = 10 ** 400
    with pytest.raises(ValueError, match=r"strikers\[0\]\.velocity = 1000.* is beyond double"):
        mimpact.run_chain(scene)
    # integers beyond 64 bits are numbers like any other: 2^64 beads are refused by the range
    scene = copy.deepcopy(c1)
    scene["chain"]["segments"][0]["count"] = 2 ** 64
    with pytest.raises(ValueError, match=r"chain\.segments\[0\]\.count = 18446744073709551616 is "
                                         r"invalid; allowed: an integer >= 1, at most 1e8"):
        mimpact.run_chain(scene)


def test_a_step_given_where_it_cannot_apply_is_refused(c1):
    adaptive = dict(c1, impact={"integrator": "adaptive", "tolerance": 1e-8})
    with pytest.raises(ValueError, match="delta_p = 1e-06 chooses the step of the impulse steps, "
                                         "but impact.integrator is \"adaptive\""):
        mimpact.run_chain(adaptive, delta_p=1e-6)
    both = dict(c1, impact={"delta_p": 1e-5, "relative_delta_p": 1e-3})
    with pytest.raises(ValueError, match="both choose the impulse step"):
        mimpact.run_chain(both)
    # relative_delta_p alone runs, and the summary says it was the step used
    relative = mimpact.run_chain(dict(c1, impact={"relative_delta_p": 1e-3}))
    assert relative.summary["relative_delta_p"] == 1e-3 and relative.delta_p is None
    compliant = dict(c1, method="compliant")
    with pytest.raises(ValueError, match="delta_p = 1e-06 is the step of the LZB method"):
        mimpact.run_chain(compliant, delta_p=1e-6)


def test_runs_beyond_the_memory_allowed_are_refused_before_they_start(c1):
    long_chain = copy.deepcopy(c1)
    long_chain["chain"]["segments"][0]["count"] = 1_000_000
    with pytest.raises(ValueError, match=r"chain\.segments \(1000000 beads\) needs about .* "
                                         r"allowed: at most 100 MB \(raise the limit with "
                                         r"max_memory=, in GB\)"):
        mimpact.run_chain(long_chain, max_memory=0.1)
    recorded = dict(c1, impact={"delta_p": 1e-9}, record={"contacts": list(range(20)),
                                                          "every": 1})
    with pytest.raises(ValueError, match=r"the recording \(record\.every = 1: at least"):
        mimpact.run_chain(recorded)
    with pytest.raises(ValueError, match="max_memory= = 0 is invalid"):
        mimpact.run_chain(c1, max_memory=0)


def test_bead_lists_are_read_only_inside_their_directory(tmp_path):
    inside = tmp_path / "scene"
    inside.mkdir()
    (tmp_path / "outside.csv").write_text("x,y,radius\n0,0,0.005\n")
    (inside / "secret.csv").write_text("x,y,radius\nTOP-SECRET,0,0.005\n")
    striker = [{"target": [0], "radius": 0.005, "velocity": [1.0, 0.0]}]
    scene = {"material": STEEL, "beads": {"file": "../outside.csv"}, "strikers": striker}
    with pytest.raises(ValueError, match="is not inside"):
        mimpact.run_packing(scene, data_dir=inside)
    scene["beads"]["file"] = str(tmp_path / "outside.csv")
    with pytest.raises(ValueError, match="is not inside"):
        mimpact.run_packing(scene, data_dir=inside)
    # allowed by data_dir
    result = mimpact.run_packing(scene, data_dir=tmp_path, delta_p=1e-6)
    assert result.post_impact_velocities.shape == (2, 2)
    # a file's lines are never echoed
    scene["beads"]["file"] = "secret.csv"
    with pytest.raises(ValueError) as raised:
        mimpact.run_packing(scene, data_dir=inside)
    assert "TOP-SECRET" not in str(raised.value) and "line 2: column x" in str(raised.value)


def test_fit_refuses_fractional_indices_and_starts_outside_the_bounds(c1):
    data = np.ones(3)
    with pytest.raises(ValueError, match=r"contacts = \[0.7, 1.9\] is not allowed"):
        mimpact.fit(c1, {"contact.restitution": (0.5, 1.0)}, "max_forces", data,
                    contacts=[0.7, 1.9])
    with pytest.raises(ValueError, match=r"start\['contact.restitution'\] = 1.5 is not allowed; "
                                         r"allowed: within its bounds \[0.5, 1.0\]"):
        mimpact.fit(c1, {"contact.restitution": (0.5, 1.0)}, "max_forces", data,
                    contacts=[0, 1, 2], start={"contact.restitution": 1.5})
    with pytest.raises(ValueError, match=r"sigma = inf is not allowed"):
        mimpact.fit(c1, {"contact.restitution": (0.5, 1.0)}, "max_forces", data,
                    contacts=[0, 1, 2], sigma=math.inf)
