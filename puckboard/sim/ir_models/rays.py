"""``rays``: the physical e-puck's IR sensors, rays through the calibrated response.

A fan of rays per sensor is cast in one pass for every ray robot near something
(:mod:`..proximity`), and each robot's firmware calibration turns the responses into
distances (:mod:`..ir_calibration`); the scene's ``noise.proximity`` applies. This module
only binds those two to the :class:`~puckboard.sim.ir_models.registry.IrSensors` contract.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..ir_calibration import IrCalibration
from ..proximity import ProximitySensors
from .registry import FloatArray, IrModel

if TYPE_CHECKING:
    from ...profile import RobotProfile
    from ..surfaces import Surfaces

__all__ = ["MODEL", "RaySensors"]


class RaySensors:
    """The ray robots' IR sensors (``robots``: world indices)."""

    def __init__(
        self,
        profiles: Sequence[RobotProfile],
        robots: Sequence[int],
        surfaces: Surfaces,
        rays: int,
        noise: float,
    ) -> None:
        self.robots = tuple(robots)
        self.noise = noise
        self.proximity = ProximitySensors(
            profiles,
            robots=robots,
            rays=rays,
            seg_start=surfaces.seg_start,
            seg_vector=surfaces.seg_vector,
            static_circles=surfaces.static_circles,
            polygons=surfaces.polygons,
            walls=surfaces.walls,
            circle_reflectance=surfaces.circle_reflectance,
            seg_reflectance=surfaces.seg_reflectance,
        )
        self.calibration = IrCalibration(profiles, self.proximity.baseline_raw)
        # the pass writes every robot's row: another model's robots get theirs back
        others = sorted(set(range(len(profiles))) - set(self.robots))
        self._others = np.array(others, dtype=np.intp) if others else None

    def sense(
        self,
        poses: Sequence[Sequence[float]],
        normals: FloatArray | None,
        distance: FloatArray,
        raw: FloatArray,
    ) -> None:
        others = self._others
        kept = None if others is None else (distance[others], raw[others])
        noise = self.noise
        if self.proximity.sense(poses, raw, noise=noise, z=normals):
            self.calibration.apply(raw, distance)
        else:
            # nobody near anything: every response is its baseline, with its noise
            far = self.proximity.far_noise(noise, normals)
            self.calibration.apply_to_nothing(raw, distance, far)
        if others is not None and kept is not None:
            distance[others], raw[others] = kept

    def recalibrate(
        self, i: int, poses: Sequence[Sequence[float]], distance: FloatArray, raw: FloatArray
    ) -> None:
        response = self.proximity.response(poses)[i]
        self.calibration.recalibrate(i, response, raw, distance)


MODEL = IrModel(
    name="rays",
    summary="rays through the calibrated IR response (the physical e-puck)",
    has_response=True,
    build=RaySensors,
)
