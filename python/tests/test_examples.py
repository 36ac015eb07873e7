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
              "coste_speed_law.py", "billiard_break.py", "oblique_impact.py"}
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


def test_billiard_break_turns_the_balls_and_keeps_momentum(tmp_path):
    """Issue 46: friction between the balls sets the object balls turning and takes energy;
    momentum and angular momentum are kept to round-off, with and without it."""
    lines = run_example("billiard_break.py", "--out", str(tmp_path)).splitlines()
    frictionless, rough = lines[0], lines[2]
    for line in (frictionless, rough):
        assert float(line.split("momentum change")[1].split()[0]) < 1e-15
        assert float(line.split("angular momentum change")[1].split()[0]) < 1e-15
    assert float(frictionless.split("slip took")[1].split()[0]) == 0.0
    assert float(rough.split("slip took")[1].split()[0]) > 0.1  # J, of 5.7
    assert "spins from 0.00 to 0.00" in lines[1]
    low, high = (float(x) for x in lines[3].split("spins from")[1].split("rad/s")[0].split("to"))
    assert low < -10 and high > 5
    assert (tmp_path / "billiard_break.png").stat().st_size > 10_000


def test_oblique_impact_draws_maw_barber_fawcetts_curve(tmp_path):
    """Issue 46: an elastic sphere's oblique impact through Hertz + Mindlin + Coulomb meets
    LAMMPS's runs to 1e-10 m/s, its contact point turns back over a range of incidences (psi_2 >
    0, Maw, Barber & Fawcett's reversal) where the rigid response rolls, and in gross slip it
    leaves on the closed form's line."""
    lines = run_example("oblique_impact.py", "--out", str(tmp_path)).splitlines()
    reversal, gross, normal, lammps = lines[:4]
    start, end = (float(x) for x in reversal.split("from")[1].split(",")[0].split("to"))
    assert 1.0 < start < 2.0 and 5.0 < end < 6.0
    assert float(reversal.split("highest")[1].split()[0]) > 1.0
    assert float(reversal.split("smallest incidence")[1]) < -0.5  # forward at small angles
    assert float(gross.split("worst")[1].split()[0]) < 1e-9
    assert float(normal.split("|e_n - 1|")[1]) < 1e-9
    assert float(lammps.split("worst")[1].split()[0]) < 1e-10
    assert (tmp_path / "maw_barber_fawcett.png").stat().st_size > 10_000
