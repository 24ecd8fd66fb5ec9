"""Behaviour layers, the subsumption arbiter, and the ready-made controllers.

A layer knows the blackboard and nothing of the backend behind it: this package imports
neither :mod:`puckboard.backends` nor :mod:`puckboard.sim`.
"""

from .clearance import ClearanceGuard
from .context import TickContext
from .controller import NO_LAYER, Controller
from .cruise import DEFAULT_SPEED, Cruise
from .go_home import GoHome
from .layer import Frame, Layer, as_behaviour
from .line_follow import LineFollow
from .line_search import LineSearch
from .obstacle import FrontBraitenbergAvoid, FrontObstacleLeftTurn, obstacle_in_front
from .presets import CONTROLLERS, improved, load_controller, robust, stock
from .suppression import HoldFor
from .wall_keep import SideWallKeep

__all__ = [
    "CONTROLLERS",
    "DEFAULT_SPEED",
    "NO_LAYER",
    "ClearanceGuard",
    "Controller",
    "Cruise",
    "Frame",
    "FrontBraitenbergAvoid",
    "FrontObstacleLeftTurn",
    "GoHome",
    "HoldFor",
    "Layer",
    "LineFollow",
    "LineSearch",
    "SideWallKeep",
    "TickContext",
    "as_behaviour",
    "improved",
    "load_controller",
    "obstacle_in_front",
    "robust",
    "stock",
]
