"""The sensor layout and the sensing pass: every IR and ground sensor of every robot at once.

A world senses after every step, for every robot, whether or not anyone reads: the
readings must describe the state at the end of the step, and the random numbers drawn
for their noise must not depend on who is watching. So the pass is built for all robots
together: each IR sensor model the robots' profiles name (:mod:`.ir_models`: the physical
e-puck's rays cast for every ray robot near something in one pass, V-REP's exact cones)
senses its robots, then all ground sensors in one query of the nearby track segments
(:mod:`.floor`).

:class:`Sensing` holds where each sensor sits (from the robots' profiles, as built) and
writes the readings into four N×k arrays, in place, so that a view of a row stays live.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from ..profile import RobotProfile
from .floor import Floor
from .ir_models import IrSensors, ir_model
from .surfaces import Surfaces

__all__ = ["Sensing"]

FloatArray = npt.NDArray[np.float64]


class Sensing:
    """The IR and ground sensors of every robot of a world; see the module docstring.

    ``rays`` rays per IR sensor; ``proximity_noise`` and ``ground_noise`` are the
    scene's σ, applied to the normals the world draws each step. ``ground_footprint``,
    when given, replaces every profile's own (m, 0: a point sample).
    """

    def __init__(
        self,
        profiles: Sequence[RobotProfile],
        floor: Floor,
        surfaces: Surfaces,
        *,
        rays: int,
        proximity_noise: float,
        ground_noise: float,
        ground_footprint: float | None = None,
    ) -> None:
        for p in profiles:
            if len(p.ground_poses) != 3:
                raise ValueError(f"profile {p.name!r} must have 3 ground sensor poses")
        n = len(profiles)
        self.floor = floor
        self._ground_noise = ground_noise
        # each robot's profile names its IR model; each model is built once, for its robots
        users: dict[str, list[int]] = {}
        for i, p in enumerate(profiles):
            users.setdefault(p.prox_model, []).append(i)
        #: the IR sensors of each model the robots use, by the model's name
        self.ir: dict[str, IrSensors] = {
            name: ir_model(name).build(profiles, robots, surfaces, rays, proximity_noise)
            for name, robots in users.items()
        }
        self._ir_of = {i: model for model in self.ir.values() for i in model.robots}
        # ground sensors: local positions, and their centroid for the segment grid
        self._ground_local = [[(q.x, q.y) for q in p.ground_poses] for p in profiles]
        self._ground_mid = [
            (sum(q[0] for q in g) / len(g), sum(q[1] for q in g) / len(g))
            for g in self._ground_local
        ]
        self._ground_reach = max(
            math.hypot(q[0] - m[0], q[1] - m[1])
            for g, m in zip(self._ground_local, self._ground_mid)
            for q in g
        )
        # each ground sensor's footprint (three per robot, robot-major like the readings)
        self._footprints = tuple(
            float(p.ground_footprint if ground_footprint is None else ground_footprint)
            for p in profiles
            for _ in range(3)
        )
        self._widest = max(self._footprints)
        self._no_track = floor.seg_start.shape[0] == 0
        self._floor_values = floor.brightness_values(np.zeros((3 * n, 2)), None, self._footprints)
        #: N×8 IR distances (m) and raw values, N×3 ground brightness (0..1) and raw values
        self.prox_distance = np.zeros((n, 8))
        self.prox_raw = np.zeros((n, 8))
        self.ground = np.zeros((n, 3))
        self.ground_raw = np.zeros((n, 3))
        self._ground_flat = self.ground.reshape(-1)  # views, written in place
        self._ground_raw_flat = self.ground_raw.reshape(-1)

    def sense(
        self,
        poses: list[list[float]],
        ir_normals: FloatArray | None,
        ground_normals: FloatArray | None,
    ) -> None:
        """Every robot's IR and ground sensors at ``poses`` (N [x, y, theta] lists).

        ``ir_normals`` (N×8) and ``ground_normals`` (3N) are the step's standard normals
        for the sensors' noise, or None for a noise-free reading (the start pose, a pose
        set by hand).
        """
        for model in self.ir.values():  # each writes its own robots' rows
            model.sense(poses, ir_normals, self.prox_distance, self.prox_raw)
        self._sense_ground(poses, ground_normals)

    def _sense_ground(self, poses: list[list[float]], normals: FloatArray | None) -> None:
        """Ground sensors: only the track segments near the robots are tested."""
        if self._no_track:
            # no line on the floor (the swarm's arena): every sensor sees the floor, as
            # the search below would find with no segment near any point
            values = self._floor_values
        else:
            # three points per robot: plain floats are cheaper than a dozen numpy calls
            points: list[complex] = []
            centres = []
            for i, (x, y, th) in enumerate(poses):
                c, s = math.cos(th), math.sin(th)
                for lx, ly in self._ground_local[i]:
                    points.append(complex(x + c * lx - s * ly, y + s * lx + c * ly))
                mx, my = self._ground_mid[i]
                centres.append((x + c * mx - s * my, y + s * mx + c * my))
            near = self.floor.segments_near(centres, self._ground_reach, self._widest)
            values = self.floor.brightness_values(np.array(points), near, self._footprints)
        # The 3N readings stay flat (robot-major, as the N×3 arrays store them). Noise,
        # clamping and the raw scale are a few float operations per reading: plain
        # floats, in the order the arrays would apply them, cost less than numpy calls.
        if normals is not None and self._ground_noise > 0:
            sigma = self._ground_noise
            values = [v + sigma * zk for v, zk in zip(values, normals.tolist())]
        values = [0.0 if v < 0.0 else 1.0 if v > 1.0 else v for v in values]
        self._ground_flat[:] = values
        self._ground_raw_flat[:] = [v * 1023.0 for v in values]

    def recalibrate_ir(self, i: int, poses: list[list[float]]) -> None:
        """Robot ``i`` re-measures its IR baselines at ``poses``, as the e-puck2 firmware
        does on request (its model's :meth:`~.ir_models.IrSensors.recalibrate`: a model
        with exact distances has no baselines, and the robot is left as it is)."""
        self._ir_of[i].recalibrate(i, poses, self.prox_distance, self.prox_raw)
