"""Scenarios: what the robots face and how they are judged.

A :class:`Scene` is plain validated data (floor, track, obstacles, walls, robots, noise,
goal, the control loop's timing) read from a scene file (:mod:`.scenefile`, TOML or
JSON; the shipped ones live in ``scenes/``) through its dict form (:mod:`.conversion`).
The engine (:mod:`puckboard.sim`) builds a world from it, and the :class:`~.judge.Judge`
scores the robots' trajectories against the scene's goal. Nothing here knows the engine,
an adapter or a controller.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .._lazy import lazy_names

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


__getattr__, __dir__ = lazy_names(__name__, _LAZY, __all__)
