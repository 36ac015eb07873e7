"""Every example of examples/python runs, and gives what it should."""

import os
import subprocess
import sys

import numpy as np

from conftest import SOURCE

EXAMPLES = SOURCE / "examples" / "python"


def run_example(name, *arguments):
    environment = dict(os.environ, PYTHONDONTWRITEBYTECODE="1")
    return subprocess.run([sys.executable, str(EXAMPLES / name), *arguments], check=True,
                          text=True, capture_output=True, env=environment).stdout


def test_every_example_is_tested():
    tested = {"bouncing_ball.py", "bead_column.py", "taper_sweep.py", "calibrate_restitution.py",
              "coste_speed_law.py"}
    assert {path.name for path in EXAMPLES.glob("*.py")} <= tested


def test_taper_sweep_draws_a_heat_map_that_grows_with_taper_and_restitution(tmp_path):
    output = run_example("taper_sweep.py", "--out", str(tmp_path))
    rows = [line.split() for line in output.splitlines()[2:-1]]
    velocities = np.array([[float(v) for v in row[1:]] for row in rows])
    assert velocities.shape == (8, 6)
    # a taper concentrates the momentum into the small balls; restitution loses less of it
    assert np.all(np.diff(velocities, axis=0) > 0) and np.all(np.diff(velocities, axis=1) > 0)
    assert (tmp_path / "taper_sweep.png").stat().st_size > 10_000


def test_calibration_draws_data_against_the_fitted_model(tmp_path):
    output = run_example("calibrate_restitution.py", "--out", str(tmp_path))
    for line in output.splitlines()[:2]:  # "<path> <value> +- <error>  (true ..., z standard ...)"
        assert float(line.split("(true")[1].split(",")[1].split()[0]) <= 2.0
    assert (tmp_path / "calibrate_restitution.png").stat().st_size > 10_000


def test_coste_speed_law_fits_the_measured_pairs(tmp_path):
    """The model's wave meets Coste, Falcon & Fauve's speeds to 2 % with the beads' nominal
    modulus, and to 0.1 % with the fitted one, a few percent from it."""
    lines = run_example("coste_speed_law.py", "--out", str(tmp_path)).splitlines()
    nominal_rms = float(lines[0].split("rms")[1].split()[0])
    young = float(lines[1].split("E =")[1].split()[0])
    fitted_rms = float(lines[1].split("rms")[1].split()[0])
    assert nominal_rms < 0.02 * 800 and fitted_rms < 0.001 * 800
    assert abs(young / 2.26e11 - 1) < 0.06
    assert (tmp_path / "coste_speed_law.png").stat().st_size > 10_000
