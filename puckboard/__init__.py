"""puckboard: behaviour-based control of the e-puck robot.

A thread-safe blackboard holds timestamped sensor records written by a robot adapter;
subsumption layers on py_trees read them and are arbitrated by priority into wheel
commands; the same controller runs on the embedded simulator, in CoppeliaSim or on a
real e-puck.

``import puckboard`` is kept fast: the names below are loaded on first use.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from ._version import __version__

__all__ = [
    "Blackboard",
    "ControlLoop",
    "Controller",
    "FakeAdapter",
    "Layer",
    "RobotAdapter",
    "WheelCommand",
    "__version__",
    "improved",
    "load_controller",
    "stock",
]

_LAZY = {
    "Blackboard": "puckboard.blackboard",
    "ControlLoop": "puckboard.control",
    "Controller": "puckboard.behaviours",
    "Layer": "puckboard.behaviours",
    "improved": "puckboard.behaviours",
    "stock": "puckboard.behaviours",
    "load_controller": "puckboard.behaviours",
    "FakeAdapter": "puckboard.adapters",
    "RobotAdapter": "puckboard.adapters",
    "WheelCommand": "puckboard.records",
}

if TYPE_CHECKING:  # pragma: no cover
    from .adapters import FakeAdapter, RobotAdapter
    from .behaviours import Controller, Layer, improved, load_controller, stock
    from .blackboard import Blackboard
    from .control import ControlLoop
    from .records import WheelCommand


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'puckboard' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(__all__)
