"""The embedded 2D e-puck simulator: the default backend, no external program needed.

The simulator knows no controller: it takes wheel speeds and gives sensor readings. The
engine's entry point is :class:`~puckboard.sim.world.World`; the scenes it is built from
live in :mod:`puckboard.scenario`.
"""

from __future__ import annotations

from typing import Any

#: Names this package re-exported before scenes moved to :mod:`puckboard.scenario`.
_MOVED_TO_SCENARIO = frozenset(
    {"Arena", "CircleObstacle", "Goal", "Noise", "PolygonObstacle", "RobotSpec", "Scene", "Track"}
)

__all__: list[str] = []


def __getattr__(name: str) -> Any:
    if name in _MOVED_TO_SCENARIO:
        from .._moved import warn_moved
        from ..scenario import scene

        warn_moved(f"puckboard.sim.{name}", f"puckboard.scenario.{name}")
        value = getattr(scene, name)
        globals()[name] = value  # warn once per name, as a plain import would
        return value
    raise AttributeError(f"module 'puckboard.sim' has no attribute {name!r}")
