"""puckboard: behaviour-based control of the e-puck robot.

A first session needs nothing deeper than this package::

    import puckboard

    result = puckboard.run_episode("two-robot-pass", controller="improved", seed=3)
    print(result.success, result.failure)

    scene = puckboard.load_scene("line-follow")
    with puckboard.open_embedded(scene) as robots:      # or open_backend("fake", scene)
        ...

A first layer neither: ``from puckboard import Layer, Controller, Frame, WheelCommand,
Cruise, LineFollow, FrontObstacleLeftTurn, SideWallKeep, run_episode`` is all the
tutorial imports.

A thread-safe blackboard holds timestamped sensor records written by a robot adapter;
subsumption layers on py_trees read them and are arbitrated by priority into wheel
commands; the same controller runs on the embedded simulator, in CoppeliaSim or on a
real e-puck.

``import puckboard`` is kept fast: the names below are loaded on first use.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ._lazy import lazy_names
from ._version import __version__

__all__ = [
    "Blackboard",
    "ControlLoop",
    "Controller",
    "Cruise",
    "FakeAdapter",
    "Frame",
    "FrontObstacleLeftTurn",
    "Layer",
    "LineFollow",
    "RobotAdapter",
    "SideWallKeep",
    "WheelCommand",
    "__version__",
    "improved",
    "load_controller",
    "load_scene",
    "open_backend",
    "open_embedded",
    "run_episode",
    "stock",
]

_LAZY = {
    "Blackboard": "puckboard.blackboard",
    "ControlLoop": "puckboard.control",
    "Controller": "puckboard.behaviours",
    "Cruise": "puckboard.behaviours",
    "Frame": "puckboard.behaviours",
    "FrontObstacleLeftTurn": "puckboard.behaviours",
    "Layer": "puckboard.behaviours",
    "LineFollow": "puckboard.behaviours",
    "SideWallKeep": "puckboard.behaviours",
    "improved": "puckboard.behaviours",
    "stock": "puckboard.behaviours",
    "load_controller": "puckboard.behaviours",
    "FakeAdapter": "puckboard.backends",
    "RobotAdapter": "puckboard.backends",
    "WheelCommand": "puckboard.records",
    "load_scene": "puckboard.scenario",
    "open_backend": "puckboard.backends.registry",
    "open_embedded": "puckboard.backends.embedded",
    "run_episode": "puckboard.control.episode",
}

if TYPE_CHECKING:  # pragma: no cover
    from .backends import FakeAdapter, RobotAdapter
    from .backends.embedded import open_embedded
    from .backends.registry import open_backend
    from .behaviours import (
        Controller,
        Cruise,
        Frame,
        FrontObstacleLeftTurn,
        Layer,
        LineFollow,
        SideWallKeep,
        improved,
        load_controller,
        stock,
    )
    from .blackboard import Blackboard
    from .control import ControlLoop
    from .control.episode import run_episode
    from .records import WheelCommand
    from .scenario import load_scene


__getattr__, __dir__ = lazy_names(__name__, _LAZY, __all__)
