"""CoppeliaSim's ``sim`` namespace: the names and constants of the release the server follows.

``zmqRemoteApi.info('sim')`` lists CoppeliaSim's *whole* ``sim`` namespace (CoppeliaSim
4.7's names and constants, :file:`coppeliasim_sim.json`, written by
``docs/make_coppeliasim_names.py``), because the official client only creates
``sim.<name>`` for listed names: a function we do not serve then reaches the server and
is answered with what it is and what is served, instead of a bare ``AttributeError`` in
the client. The constants keep CoppeliaSim's values, so that a client's
``sim.handle_world`` means here what it means there.
"""

from __future__ import annotations

import json
from importlib import resources
from typing import Any

__all__ = ["CONSTANTS", "NAMES", "PROGRAM_REVISION", "PROGRAM_VERSION", "coppeliasim_names"]


def coppeliasim_names() -> dict[str, Any]:
    """CoppeliaSim 4.7's ``sim`` namespace: ``functions`` (names) and ``constants``."""
    text = resources.files(__package__).joinpath("coppeliasim_sim.json").read_text("utf-8")
    return json.loads(text)  # type: ignore[no-any-return]


NAMES = coppeliasim_names()
#: CoppeliaSim's constants (its values; a client sees them as ``sim.<name>``).
CONSTANTS: dict[str, int] = dict(NAMES["constants"])
_C = CONSTANTS
HANDLE_WORLD = _C["handle_world"]
HANDLE_PARENT = _C["handle_parent"]
HANDLE_SCENE = _C["handle_scene"]
HANDLE_ALL = _C["handle_all"]
SCRIPTTYPE_CHILD = _C["scripttype_childscript"]
SIMULATION_STOPPED = _C["simulation_stopped"]
SIMULATION_PAUSED = _C["simulation_paused"]
SIMULATION_ADVANCING_RUNNING = _C["simulation_advancing_running"]
#: The CoppeliaSim release whose API and behaviour the server follows.
PROGRAM_VERSION = 40700
PROGRAM_REVISION = 2
