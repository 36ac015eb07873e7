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
