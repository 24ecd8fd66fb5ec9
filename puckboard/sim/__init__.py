"""The embedded 2D e-puck simulator: the default backend, no external program needed.

The simulator knows no controller: it takes wheel speeds and gives sensor readings.
"""

from ..scenario.scene import (
    Arena,
    CircleObstacle,
    Goal,
    Noise,
    PolygonObstacle,
    RobotSpec,
    Scene,
    Track,
)

__all__ = [
    "Arena",
    "CircleObstacle",
    "Goal",
    "Noise",
    "PolygonObstacle",
    "RobotSpec",
    "Scene",
    "Track",
]
