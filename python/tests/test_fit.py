"""fit(): scene parameters from measurements, by least squares over runs of the model."""

import sys

import numpy as np
import pytest

import mimpact
from conftest import SOURCE

pytestmark = pytest.mark.filterwarnings("ignore:make_current is deprecated:DeprecationWarning")

sys.path.insert(0, str(SOURCE / "examples" / "python"))
import calibrate_restitution as melo  # noqa: E402  (the example's scene and data)

sys.path.pop(0)


def test_melos_chain_gives_back_e_and_v_within_two_standard_errors():
    """Section 5.2 of Nguyen & Brogliato: the peak forces along the monodisperse part of the M
    chain, made at e = 0.965 and V = 0.62 m/s with 2 % noise, give both values back."""
    measured = melo.synthetic_measurements()
    fitted = melo.calibrate(measured)
    for path, true in melo.TRUE.items():
        error = fitted.standard_errors[path]
        assert 0 < error < 0.02 * true
        assert abs(fitted.values[path] - true) <= 2 * error, (path, fitted.values[path], error)
    assert fitted.residuals.shape == (len(melo.CONTACTS),)
    # chi^2 of 15 data and 2 parameters: 13 on average
    assert float(fitted.residuals @ fitted.residuals) < 30
    assert 3 <= fitted.runs <= 60


def test_the_jacobians_runs_on_a_dask_cluster_give_the_same_fit():
    distributed = pytest.importorskip("distributed")
    measured = melo.synthetic_measurements()
    local = melo.calibrate(measured)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        remote = melo.calibrate(measured, client=client)
    assert remote.values == local.values and remote.runs == local.runs


def test_a_callable_observable_and_exact_data():
    """C1 (e = 1) scales with the striker's speed: the last bead's speed measured at 0.8 m/s
    gives 0.8 m/s back, with no scatter to make an error of."""
    scene = mimpact.read_scene(SOURCE / "examples/scenes/c1.json")
    scene["impact"] = {"integrator": "adaptive", "tolerance": 1e-10}
    scene["strikers"][0]["velocity"] = 0.8
    measured = mimpact.run_chain(scene).post_impact_velocities[-1]
    scene["strikers"][0]["velocity"] = 1.0
    fitted = mimpact.fit(scene, {"strikers.0.velocity": (0.1, 2.0)},
                         lambda result: result.post_impact_velocities[-1:], [measured])
    assert fitted.values["strikers.0.velocity"] == pytest.approx(0.8, rel=1e-7)
    assert fitted.standard_errors["strikers.0.velocity"] < 1e-7


@pytest.mark.parametrize(
    "arguments, message",
    [
        (dict(parameters={"contact.restitutio": (0.8, 1.0)}), "restitutio"),
        (dict(parameters={"contact.restitution": (0.8, 1.2)}),
         "bounds outside the field's allowed range.*restitution = 1.2 is invalid"),
        (dict(parameters={"contact.restitution": (0.9, 0.8)}), "lower < upper"),
        (dict(parameters={"contact.restitution": 0.9}), r"allowed: \(lower, upper\)"),
        (dict(observable="forces"), "observable = 'forces' is not allowed"),
        (dict(bodies=[1]), "bodies given for max_forces"),
        (dict(contacts=[99]), r"contacts = \[99\] is not allowed; allowed: indices 0 <= i < 20"),
        (dict(data=[1.0, 2.0]), "data has 2 values; allowed: 20"),
        (dict(sigma=-1.0), "sigma = -1.0 is not allowed"),
    ],
)
def test_bad_input_is_named(arguments, message):
    scene = mimpact.read_scene(SOURCE / "examples/scenes/c1.json")
    scene["impact"] = {"integrator": "adaptive", "tolerance": 1e-6}
    call = dict(parameters={"contact.restitution": (0.8, 1.0)}, observable="max_forces",
                data=np.ones(20))
    call.update(arguments)
    with pytest.raises(ValueError, match=message):
        mimpact.fit(scene, **call)
