"""Shared fixtures for the sweep tests: a short scene."""

from __future__ import annotations

import dataclasses

import pytest
from sweep_helpers import DURATION


@pytest.fixture(scope="session")
def short_scene():
    """The shipped line-follow scene, cut to a few seconds so sweeps stay quick."""
    from puckboard.scenario.scenefile import load_scene

    return dataclasses.replace(load_scene("line-follow"), duration=DURATION)
