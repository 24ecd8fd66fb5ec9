"""Scenarios: what the robots face and how they are judged.

A :class:`Scene` is plain validated data (floor, track, obstacles, walls, robots, noise,
goal, the control loop's timing) read from a scene file (:mod:`.scenefile`, TOML or JSON; the shipped ones live in
``scenes/``) through its dict form (:mod:`.conversion`). The engine
(:mod:`puckboard.sim`) builds a world from it, and the :class:`~.judge.Judge` scores the
robots' trajectories against the scene's goal. Nothing here knows the engine, an adapter
or a controller.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

# Loaded on first use, as ``puckboard`` itself loads its parts: the command line reads
# the variations' and settings' names from here while it builds its parser, before
# numpy may be imported (puckboard.sweep.signals says why).
_LAZY = {
    "scene_from_dict": ".conversion",
    "scene_to_dict": ".conversion",
    **dict.fromkeys(
        (
            "Arena",
            "CircleObstacle",
            "Control",
            "Goal",
            "Noise",
            "PolygonObstacle",
            "RobotSpec",
            "Scene",
            "Track",
        ),
        ".scene",
    ),
    "load_scene": ".scenefile",
    "scene_names": ".scenefile",
}

if TYPE_CHECKING:  # pragma: no cover
    from .conversion import scene_from_dict, scene_to_dict
    from .scene import (
        Arena,
        CircleObstacle,
        Control,
        Goal,
        Noise,
        PolygonObstacle,
        RobotSpec,
        Scene,
        Track,
    )
    from .scenefile import load_scene, scene_names

__all__ = [
    "Arena",
    "CircleObstacle",
    "Control",
    "Goal",
    "Noise",
    "PolygonObstacle",
    "RobotSpec",
    "Scene",
    "Track",
    "load_scene",
    "scene_from_dict",
    "scene_names",
    "scene_to_dict",
]


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(module, __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(__all__)
