"""The kernel from Python: bodies, interactions, laws, a simulation chosen by registry names,
observers as Python callables; and the Python examples, against the C++ ones."""

import math
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import mimpact
from conftest import SOURCE
from test_examples import run_example

EXAMPLES = SOURCE / "examples" / "python"


def cpp_example(name):
    build = os.environ.get("MIMPACT_BUILD_DIR")
    binary = pathlib.Path(build or "", "examples", name, name)
    if not build or not binary.exists():
        pytest.skip("the C++ examples are not built beside the module")
    return subprocess.run([str(binary)], check=True, text=True, capture_output=True).stdout


def without_timing(output):
    """The lines but the last, which holds the wall time."""
    return output.strip().splitlines()[:-1]


@pytest.mark.parametrize("name", ["bouncing_ball", "bead_column"])
def test_python_examples_print_the_cpp_examples_numbers(name):
    assert without_timing(run_example(name + ".py")) == without_timing(cpp_example(name))


def test_bouncing_ball_follows_the_rigid_series():
    sys.path.insert(0, str(EXAMPLES))
    try:
        import bouncing_ball
    finally:
        sys.path.pop(0)
    mass, bounces, resting, summary = bouncing_ball.bounce()
    speeds = [speed for _, _, speed in bounces[:5]]
    first = math.sqrt(2 * 9.81 * (1.0 - 0.01))
    for k, speed in enumerate(speeds):
        assert speed == pytest.approx(0.8 ** (k + 1) * first, rel=1e-9)
    assert resting[0][1] == pytest.approx(mass * 9.81, rel=1e-9)
    assert summary.status == "reached_end"


def oscillator(**forces):
    """A unit mass on a spring of stiffness 4 (omega = 2), q(0) = 1, no contact. As in Siconos,
    M q'' + F_int(t, q, v) = F_ext(t): the spring's internal force is +4 q."""
    body = mimpact.LagrangianDS([1.0], [0.0], [[1.0]], name="oscillator", **forces)
    system = mimpact.NonSmoothDynamicalSystem()
    system.add(body)
    return body, system


def test_lagrangian_ds_with_python_forces_meets_the_exact_motion():
    body, system = oscillator(internal_force=lambda t, q, v: 4.0 * q)
    simulation = mimpact.Simulation(system)
    samples = []
    simulation.schedule_outputs(0.0, 0.25, 2.0)
    simulation.add_observer(on_output=lambda state, *_: samples.append(
        (state.time, state.system.system(0).position[0])))
    simulation.run(0.0, 2.0)
    times, positions = np.array(samples).T
    assert len(times) == 9
    np.testing.assert_allclose(positions, np.cos(2.0 * times), atol=1e-8)


def test_a_mass_given_as_a_callable():
    body = mimpact.LagrangianDS([1.0], [0.0], lambda q: [[2.0]],
                                internal_force=lambda t, q, v: 8.0 * q)
    system = mimpact.NonSmoothDynamicalSystem()
    system.add(body)
    mimpact.Simulation(system).run(0.0, 1.0)
    assert body.position[0] == pytest.approx(math.cos(2.0), abs=1e-8)


def test_an_observer_ends_the_run_with_its_reason():
    body, system = oscillator(internal_force=lambda t, q, v: 4.0 * q)
    simulation = mimpact.Simulation(system)
    simulation.schedule_outputs(0.0, 0.01, 10.0)  # the loop stops at these times
    simulation.add_observer(on_step=lambda state, step: "crossed zero" if body.position[0] < 0
                            else None)
    summary = simulation.run(0.0, 10.0)
    assert summary.status == "terminated" and summary.reason == "crossed zero"
    assert math.pi / 4 < summary.end_time < math.pi / 4 + 0.01


def test_errors_in_python_callables_reach_the_caller():
    body, system = oscillator(internal_force=lambda t, q, v: [1.0, 2.0])
    with pytest.raises(ValueError, match="internal_force.*returned 2 values; allowed: 1"):
        mimpact.Simulation(system).run(0.0, 1.0)
    body, system = oscillator(external_force=lambda t: 1.0 / 0.0)
    with pytest.raises(ZeroDivisionError):
        mimpact.Simulation(system).run(0.0, 1.0)


def test_bad_input_names_the_field():
    with pytest.raises(ValueError, match="restitution e = 2 is invalid; allowed: 0 <= e <= 1"):
        mimpact.LzbLaw(stiffness=1e9, restitution=2.0)
    with pytest.raises(ValueError, match="unknown"):
        mimpact.LzbLaw(stiffness=1e9, colour="red")
    body, system = oscillator()
    with pytest.raises(ValueError, match='no one-step integrator named "leapfrog"'):
        mimpact.Simulation(system, integrator="leapfrog")
    with pytest.raises(ValueError, match="samples_per_step"):
        mimpact.Simulation(system, integrator_options={"samples_per_step": 0})
    with pytest.raises(ValueError, match="solves no impact"):
        mimpact.Simulation(system, integrator="compliant", impacts="lzb")
    with pytest.raises(ValueError, match="allowed: None to go on, or a string"):
        simulation = mimpact.Simulation(system)
        simulation.add_observer(on_step=lambda state, step: 42)
        simulation.run(0.0, 1.0)


@pytest.mark.parametrize("integrator", ["event-driven", "compliant"])
@pytest.mark.parametrize("degrees, mu", [(10.0, 0.5), (60.0, 0.05), (30.0, 0.2)])
def test_a_spinning_ball_on_a_rough_floor_meets_the_closed_form(degrees, mu, integrator):
    """A solid ball (x, y, angle) strikes a rough floor at incidence theta with top spin, the
    floor's tangent row T = (1, 0, R) giving the slip s = v_x + R w. P_n = (1 + e) m V cos(theta);
    the ball leaves rolling (s+ = 0, v_x+ = v_x - 2/7 s-) unless its slip outlasts the impact,
    |s-| >= 7/2 mu (1 + e) V cos(theta), where v_x drops by mu (1 + e) V cos(theta)
    (docs/model.md, section 16): the LZB impact of the event-driven scheme, and the compliant
    contact, rigid across (its ContactForceHistory gives the tangential impulse and the slip's
    work)."""
    mass, radius, speed, spin, e = 0.17, 0.0286, 2.0, 20.0, 0.6
    inertia = 0.4 * mass * radius**2
    theta = math.radians(degrees)
    v = [speed * math.sin(theta), -speed * math.cos(theta), spin]
    ball = mimpact.LagrangianLinearTIDS([0.0, radius, 0.0], v,
                                        np.diag([mass, mass, inertia]).tolist(), name="ball")
    law = mimpact.LzbLaw(stiffness=1e9, restitution=e, friction=mu)
    floor = mimpact.LinearRelation([0.0, 1.0, 0.0], -radius, tangents=[[1.0, 0.0, radius]])
    system = mimpact.NonSmoothDynamicalSystem()
    system.add(ball)
    system.add(mimpact.Interaction(ball, floor, law, "floor"))
    if integrator == "compliant":
        simulation = mimpact.Simulation(system, integrator="compliant", integrator_options={
            "relative_tolerance": 1e-12, "absolute_tolerance": 1e-16})
    else:
        simulation = mimpact.Simulation(system, integrator="event-driven", impact_options={
            "integrator": "adaptive", "tolerance": 1e-12})
        assert simulation.contact_force_history is None
    impacts = []
    simulation.add_observer(on_impact=lambda state, impact: impacts.append(impact))
    simulation.run(0.0, 1e-3)
    after = ball.velocity
    normal, slip = speed * math.cos(theta), v[0] + radius * spin
    drop = mu * (1 + e) * normal
    if abs(slip) >= 3.5 * drop:
        expected_vx, expected_slip = v[0] - math.copysign(drop, slip), slip - math.copysign(3.5 * drop, slip)
    else:
        expected_vx, expected_slip = v[0] - slip / 3.5, 0.0
    assert after[1] == pytest.approx(e * normal, abs=1e-9 * speed)
    assert after[0] == pytest.approx(expected_vx, abs=1e-9 * speed)
    assert after[0] + radius * after[2] == pytest.approx(expected_slip, abs=1e-9 * speed)
    if integrator == "compliant":
        history = simulation.contact_force_history
        assert history.impulse[0] == pytest.approx(mass * (1 + e) * normal, rel=1e-9)
        assert history.tangential_impulse[0, 0] == pytest.approx(mass * (after[0] - v[0]),
                                                                 abs=1e-9 * mass * speed)
        slip_work, loss = history.slip_work[0], ball_energy(mass, inertia, v) - ball_energy(
            mass, inertia, after)
        assert slip_work > 0.0
        assert loss == pytest.approx(history.work[0] + slip_work - history.stored_energy[0],
                                     rel=1e-9)
        return
    assert len(impacts) == 1
    assert impacts[0].slip_after[0] == pytest.approx(expected_slip, abs=1e-9 * speed)
    assert impacts[0].slip_work[0] > 0.0


def ball_energy(mass, inertia, v):
    return 0.5 * mass * (v[0] ** 2 + v[1] ** 2) + 0.5 * inertia * v[2] ** 2


def test_friction_on_a_relation_without_tangents_is_refused():
    ball = mimpact.LagrangianLinearTIDS([0.01], [-1.0], [[0.1]], name="ball")
    system = mimpact.NonSmoothDynamicalSystem()
    system.add(ball)
    system.add(mimpact.Interaction(ball, mimpact.LinearRelation([1.0], -0.01),
                                   mimpact.LzbLaw(stiffness=1e9, friction=0.3), "floor"))
    simulation = mimpact.Simulation(system, integrator="event-driven",
                                    impact_options={"integrator": "adaptive"})
    with pytest.raises(ValueError, match="interaction 'floor': friction = 0.3"):
        simulation.run(0.0, 1e-3)
    with pytest.raises(ValueError, match="tangent rows"):
        mimpact.LinearRelation([1.0, 0.0], 0.0, tangents=[[1.0, 0.0, 0.0]])
