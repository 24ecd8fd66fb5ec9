"""Shared test helpers live in tests/support/, importable from every test folder.

Fixtures more than one folder uses are here; helpers are imported from tests/support by
their own module names, never from a ``conftest`` (every folder's conftest shares that
name, so two folders run together would collect one folder's helpers for the other's).
"""

import dataclasses
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent / "support"))

from sweep_helpers import DURATION  # found through the path set above


@pytest.fixture(scope="session")
def short_scene():
    """The shipped line-follow scene, cut to a few seconds so sweeps and sensitivity
    analyses stay quick."""
    from puckboard.scenario.scenefile import load_scene

    return dataclasses.replace(load_scene("line-follow"), duration=DURATION)
