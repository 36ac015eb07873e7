"""Shared fixtures: the repository's scenes, and the command line built beside the module."""

import json
import os
import pathlib
import re

import pytest

SOURCE = pathlib.Path(os.environ.get("MIMPACT_SOURCE_DIR", pathlib.Path(__file__).parents[2]))


def read_scene(relative):
    """A scene file of the repository as a dict (its // comments dropped)."""
    text = (SOURCE / relative).read_text()
    return json.loads(re.sub(r"^\s*//.*$", "", text, flags=re.MULTILINE))


@pytest.fixture
def c1():
    return read_scene("examples/scenes/c1.json")


@pytest.fixture
def cli():
    path = os.environ.get("MIMPACT_CLI")
    if not path:
        pytest.skip("MIMPACT_CLI not set (run through ctest)")
    return path


def rough_packing():
    """A 4 x 4 hexagonal packing of steel beads with friction 0.3, struck 3 mm off-centre by a
    striker spinning at -150 rad/s (issue 46), for the adaptive LZB at tolerance 1e-10."""
    return {"material": {"density": 7780, "young": 203e9, "poisson": 0.3},
            "lattice": {"type": "hexagonal", "rows": 4, "columns": 4, "radius": 0.005},
            "strikers": [{"target": [0, 1], "radius": 0.005, "velocity": [0, 1],
                          "offset": 0.003, "spin": -150}],
            "contact": {"restitution": 0.9, "friction": 0.3},
            "impact": {"integrator": "adaptive", "tolerance": 1e-10},
            "configuration_check": {"enabled": False}}
