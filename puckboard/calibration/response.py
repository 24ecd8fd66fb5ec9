"""What each IR sensor should read in front of a wall: the simulator's own model, asked.

A calibration fits every sensor's gain and offset so that the simulator, given them,
predicts that sensor. So the response it fits against must be the very one the
simulator computes, not a second model of the same thing: :class:`WallModel` builds a
world with one long, straight wall and the robot's profile with every gain 1 and every
offset 0, places the robot where the calibration says it was (its distance from the
wall, its heading) and reads the noise-free calibrated values the engine computes there
(``World.set_pose`` senses without noise: what a robot's many averaged readings tend to).
Each sensor ``i`` then answers ``E_i(D, θ)`` at gain 1, and a sensor of gain ``g`` and
offset ``o`` answers ``g·E_i + o`` on average (docs/profiles.md gives the model:
``clip(g·Σw·T(d)·(1 + σz) − g·T(∞) + o, 0, 4095)``, whose noise averages out).

The rays, the aperture, the sensors' poses and the response table are all the profile's
and the engine's; nothing here restates them.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import numpy.typing as npt

from ..ir_response import cutoff_value
from ..profile import RobotProfile
from ..records import PROX_NAMES
from ..scenario.scene import Noise, PolygonObstacle, RobotSpec, Scene
from ..sim.world import World

__all__ = ["WALL_HALF_LENGTH", "WallModel"]

FloatArray = npt.NDArray[np.float64]

#: Half the model wall's length (m): from a robot 10 cm away, a sensor's outermost ray
#: (7.5° off its axis) meets the wall within a few centimetres of the axis, so 1 m is an
#: endless wall for every ray that matters.
WALL_HALF_LENGTH = 1.0
#: Distances (m) from the sensor at which :meth:`WallModel.detection_end` looks.
_DETECTION_GRID = np.linspace(0.0, 0.09, 901)


class WallModel:
    """The simulator's IR response of ``profile`` (gains 1, offsets 0) facing a wall.

    The wall's face is the line x = 0 of the model's world, the wall itself at x > 0;
    a robot at distance ``D`` (centre to wall) and heading ``θ`` (0: facing the wall,
    counter-clockwise positive) stands at (−D, 0, θ).
    """

    def __init__(self, profile: RobotProfile) -> None:
        n = len(profile.prox_poses)
        unit = dataclasses.replace(profile, ir_gain=(1.0,) * n, ir_offset=(0.0,) * n)
        self.profile = unit
        wall = PolygonObstacle(
            np.array(
                [
                    [0.0, -WALL_HALF_LENGTH],
                    [0.05, -WALL_HALF_LENGTH],
                    [0.05, WALL_HALF_LENGTH],
                    [0.0, WALL_HALF_LENGTH],
                ]
            ),
            name="wall",
        )
        far = -0.5  # built clear of the wall; every query places the robot itself
        scene = Scene(
            name="ir-calibration-wall-model",
            robots=(RobotSpec("robot", far, 0.0, 0.0, profile=unit),),
            obstacles=(wall,),
            noise=Noise(),
        )
        self._world = World(scene)
        self.cutoff = cutoff_value(profile.prox_max_distance)
        self._facing: dict[str, FloatArray] = {}

    def expected(self, distance: float, heading: float) -> FloatArray:
        """The 8 sensors' mean calibrated values at gain 1, offset 0 (ps0..ps7), with the
        robot's centre ``distance`` (m) from the wall and turned ``heading`` (rad) from
        facing it."""
        self._world.set_pose(0, -float(distance), 0.0, float(heading))
        return np.array(self._world.prox_raw[0], dtype=float)

    def facing(self, sensor: str, gap: float) -> float:
        """Gain-1 value of ``sensor`` looking straight at the wall from ``gap`` m (the
        sensor's own distance to the wall along its axis)."""
        i = PROX_NAMES.index(sensor)
        pose = self.profile.prox_poses[i]
        heading = -pose.heading
        # the sensor's distance ahead of the centre, towards the wall, once turned
        ahead = pose.x * math.cos(heading) - pose.y * math.sin(heading)
        return float(self.expected(gap + ahead, heading)[i])

    def detection_end(self, sensor: str, gain: float, offset: float) -> float | None:
        """How far from a wall straight ahead ``sensor`` of ``gain`` and ``offset`` stops
        detecting it (m from the sensor): where its mean value falls to the cut-off below
        which a robot's software reads nothing (the value at the profile's
        ``prox_max_distance``). 0 when it never rises above the cut-off; ``None`` when it
        never falls to it (an offset above the cut-off: the sensor always sees something).
        """
        curve = self._facing.get(sensor)
        if curve is None:
            curve = np.array([self.facing(sensor, d) for d in _DETECTION_GRID])
            self._facing[sensor] = curve
        values = gain * curve + offset
        if values[0] <= self.cutoff:
            return 0.0
        below = np.flatnonzero(values <= self.cutoff)
        if below.size == 0:
            return None
        k = int(below[0])
        # linear between the last grid point above the cut-off and the first at or below
        d0, d1 = _DETECTION_GRID[k - 1], _DETECTION_GRID[k]
        v0, v1 = values[k - 1], values[k]
        return float(d0 + (v0 - self.cutoff) * (d1 - d0) / (v0 - v1))
