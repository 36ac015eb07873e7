"""The --out directory of the command line is complete or absent (issue 22, item 4): killed by
SIGTERM or SIGKILL at any moment of a run, or failing to write (a full disk, here a file size
limit), a run leaves either the earlier directory as it was or its own whole; what a SIGKILL
leaves beside it is an empty staging directory, which the next run removes."""

import json
import os
import pathlib
import resource
import signal
import subprocess
import time

import pytest

STEEL = {"density": 7780, "young": 203e9, "poisson": 0.3}


def packing_scene(rows, every):
    """A hexagonal packing whose frames make an output of tens of megabytes."""
    return {"material": STEEL,
            "lattice": {"type": "hexagonal", "rows": rows, "columns": rows, "radius": 0.005},
            "strikers": [{"target": [0, rows // 2], "radius": 0.005, "velocity": [0.0, 1.0]}],
            "impact": {"delta_p": 1e-6},
            "record": {"every": every, "frames": 1, "contacts": [0]}}


def contents(directory):
    """{name: bytes} of a directory, or None when it does not exist."""
    if not directory.exists():
        return None
    return {path.name: path.read_bytes() for path in sorted(directory.iterdir())}


def leftovers(parent):
    return [path for path in parent.iterdir() if ".mimpact-staging-" in path.name]


@pytest.fixture
def runs(tmp_path, cli):
    """The scene files, the earlier run's directory and the complete new one, for comparison."""
    (tmp_path / "old.json").write_text(json.dumps(packing_scene(6, 50)))
    (tmp_path / "new.json").write_text(json.dumps(packing_scene(10, 4)))
    reference = tmp_path / "reference"
    start = time.monotonic()
    subprocess.run([cli, "packing", "new.json", "--out", str(reference), "--quiet"],
                   cwd=tmp_path, check=True)
    seconds = time.monotonic() - start
    expected = contents(reference)
    assert sum(len(text) for text in expected.values()) > 10e6
    # summary.json holds the wall time, which differs from run to run: the names and the frames
    return tmp_path, seconds, (sorted(expected), expected["frame_forces.csv"])


def start_run(cli, work, **options):
    return subprocess.Popen([cli, "packing", "new.json", "--out", "out", "--quiet"], cwd=work,
                            stderr=subprocess.PIPE, **options)


def judge(work, old, expected):
    """The directory is the old one untouched or a new one whole."""
    now = contents(work / "out")
    if now == old:
        return "old"
    names, frames = expected
    assert now is not None and sorted(now) == names, sorted(now or {})
    assert json.loads(now["summary.json"])["status"] == "terminated"
    assert now["frame_forces.csv"] == frames
    return "new"


@pytest.mark.parametrize("which", [signal.SIGTERM, signal.SIGKILL])
def test_a_killed_run_leaves_the_old_directory_or_a_whole_new_one(runs, cli, which):
    work, seconds, expected = runs
    outcomes = set()
    for k in range(1, 7):
        subprocess.run([cli, "packing", "old.json", "--out", "out", "--quiet"], cwd=work,
                       check=True)
        old = contents(work / "out")
        run = start_run(cli, work)
        time.sleep(seconds * k / 6)
        run.send_signal(which)
        run.wait()
        outcomes.add(judge(work, old, expected))
        left = leftovers(work)
        if which == signal.SIGTERM:
            assert not left, left  # SIGTERM waits for the directory to be whole or absent
        else:  # at most the staging directory: its files are unlinked until the instant before
            # it is renamed into place, and the next run removes it
            assert all(path.is_dir() for path in left), left
    # the next run removes what a killed one left
    subprocess.run([cli, "packing", "old.json", "--out", "out", "--quiet"], cwd=work, check=True)
    assert not leftovers(work)
    assert "old" in outcomes  # the kills fell before the end, at least once


def test_a_write_that_fails_keeps_the_old_directory(runs, cli):
    work, _, _ = runs
    subprocess.run([cli, "packing", "old.json", "--out", "out", "--quiet"], cwd=work, check=True)
    old = contents(work / "out")
    megabyte = 1 << 20  # a file size limit: the writes past it fail as on a full disk
    run = start_run(cli, work, preexec_fn=lambda: resource.setrlimit(
        resource.RLIMIT_FSIZE, (megabyte, megabyte)))
    _, error = run.communicate()
    assert run.returncode == 1
    assert "cannot write the file" in error.decode() and "nothing was written" in error.decode()
    assert contents(work / "out") == old
    assert not leftovers(work)


def test_a_new_directory_is_absent_after_a_failed_write(runs, cli):
    work, _, _ = runs
    megabyte = 1 << 20
    run = start_run(cli, work, preexec_fn=lambda: resource.setrlimit(
        resource.RLIMIT_FSIZE, (megabyte, megabyte)))
    run.communicate()
    assert run.returncode == 1
    assert not (work / "out").exists() and not leftovers(work)
