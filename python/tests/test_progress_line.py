"""A long run says where it is (issue 47): one line updated in place on a terminal, from the
command line unless --quiet or stderr is not a terminal, and from Python with progress=True."""

import json
import os
import pty
import subprocess

import mimpact

# some 3 s: a 24 x 24 hexagonal packing's compliant contacts at tolerance 1e-10 until 1 ms
LONG_PACKING = {"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
                "lattice": {"type": "hexagonal", "rows": 24, "columns": 24, "radius": 0.005},
                "strikers": [{"target": [0, 12], "radius": 0.005, "velocity": [0.0, 1.0]}],
                "contact": {"restitution": 0.9}, "method": "compliant",
                "compliant": {"tolerance": 1e-10, "end_time": 1e-3}}


def read_all(descriptor):
    chunks = []
    while True:
        try:
            chunk = os.read(descriptor, 65536)
        except OSError:  # the terminal's other end is closed
            break
        if not chunk:
            break
        chunks.append(chunk)
    return b"".join(chunks).decode()


def assert_progress_line(text):
    lines = [line for line in text.split("\r") if line.strip()]
    assert lines, text
    assert all(line.startswith("compliant contacts: t = ") for line in lines[:-1])
    assert " of 0.001 s (" in lines[0] and " steps, " in lines[0] and "contacts in motion" in lines[0]


def test_python_shows_progress_only_when_asked(capfd):
    shown = mimpact.run_packing(LONG_PACKING, progress=True)
    err = capfd.readouterr().err
    assert_progress_line(err)
    assert err.endswith("\n")
    assert shown.summary["status"] == "end_time"


def test_the_command_line_shows_progress_on_a_terminal_only(cli, tmp_path):
    (tmp_path / "scene.json").write_text(json.dumps(LONG_PACKING))
    runs = {}
    for name, arguments in {"terminal": [], "quiet": ["--quiet"], "pipe": []}.items():
        command = [cli, "packing", str(tmp_path / "scene.json"), "--out", str(tmp_path / name),
                   *arguments]
        if name == "pipe":
            runs[name] = (subprocess.Popen(command, stdout=subprocess.DEVNULL,
                                           stderr=subprocess.PIPE, text=True), None)
            continue
        main, other = pty.openpty()
        runs[name] = (subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=other), main)
        os.close(other)
    err = {}
    for name, (process, main) in runs.items():
        err[name] = read_all(main) if main is not None else process.communicate(timeout=120)[1]
        assert process.wait(timeout=120) == 0
        if main is not None:
            os.close(main)
    assert_progress_line(err["terminal"].split("\n")[0])
    assert "\r" not in err["quiet"] and err["quiet"] == ""
    assert "\r" not in err["pipe"] and "compliant contacts integrated in time" in err["pipe"]
    # the report follows on its own line, and the outputs are alike
    assert "\n" + str(tmp_path / "scene.json") + ": 576 beads" in err["terminal"].replace("\r\n", "\n")
    summaries = [json.loads((tmp_path / name / "summary.json").read_text()) for name in runs]
    for summary in summaries:
        summary.pop("wall_time")
        summary["error_estimate"].pop("companion_seconds")  # times, not outcomes
    assert summaries[0] == summaries[1] == summaries[2]
