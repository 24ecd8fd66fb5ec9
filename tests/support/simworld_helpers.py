"""Small hand-made scenes for the simulator tests: known geometry, known readings."""

from __future__ import annotations

import math

import numpy as np

from puckboard.scenario.scene import (
    Arena,
    CircleObstacle,
    Noise,
    PolygonObstacle,
    RobotSpec,
    Scene,
    Track,
)


def robot(name: str = "a", x: float = 0.0, y: float = 0.0, theta: float = 0.0, **kw) -> RobotSpec:
    return RobotSpec(name, x, y, theta, **kw)


def empty_scene(*robots: RobotSpec, noise: Noise | None = None, **kw) -> Scene:
    """Nothing but the robots on an endless light floor."""
    return Scene("test", robots=robots or (robot(),), noise=noise or Noise(), **kw)


def loop_track(rx: float = 0.5, ry: float = 0.3, n: int = 120, width: float = 0.02) -> Track:
    a = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    return Track(np.column_stack([rx * np.cos(a), ry * np.sin(a)]), width=width)


def noisy() -> Noise:
    return Noise(wheel_speed=0.05, proximity=0.05, ground=0.02, start_jitter=0.0)


def pass_scene(noise: Noise | None = None) -> Scene:
    """Two robots on a loop heading towards each other, two obstacles, walls."""
    return Scene(
        "mini-pass",
        robots=(
            robot("a", 0.5, 0.0, math.pi / 2),
            robot("b", -0.5, 0.0, -math.pi / 2, colour=(40, 60, 200)),
        ),
        track=loop_track(),
        obstacles=(
            CircleObstacle(0.0, 0.3, 0.03),
            PolygonObstacle([[0.0, -0.33], [0.05, -0.33], [0.05, -0.27], [0.0, -0.27]]),
        ),
        arena=Arena(-0.7, -0.5, 0.7, 0.5),
        noise=noise or Noise(),
    )
