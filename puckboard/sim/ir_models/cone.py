"""``cone``: V-REP's proximity sensors, the exact distance to the nearest point in a cone.

The geometry is :mod:`..cone`'s; this module binds it to the
:class:`~puckboard.sim.ir_models.registry.IrSensors` contract. The cones are exact: the scene's
``noise.proximity`` does not apply, and there is no response to calibrate.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from ..cone import ConeSensors
from .registry import FloatArray, IrModel

if TYPE_CHECKING:
    from ...profile import RobotProfile
    from ..surfaces import Surfaces

__all__ = ["MODEL", "ConeModel"]


class ConeModel:
    """The cone robots' IR sensors (``robots``: world indices)."""

    def __init__(
        self,
        profiles: Sequence[RobotProfile],
        robots: Sequence[int],
        surfaces: Surfaces,
        rays: int,
        noise: float,
    ) -> None:
        self.robots = tuple(robots)
        self.cones = ConeSensors(
            profiles,
            robots,
            static_circles=surfaces.static_circles,
            seg_start=surfaces.seg_start,
            seg_vector=surfaces.seg_vector,
            polygons=surfaces.polygons,
            walls=surfaces.walls,
        )

    def sense(
        self,
        poses: Sequence[Sequence[float]],
        normals: FloatArray | None,
        distance: FloatArray,
        raw: FloatArray,
    ) -> None:
        self.cones.sense(poses, distance, raw)

    def recalibrate(
        self, i: int, poses: Sequence[Sequence[float]], distance: FloatArray, raw: FloatArray
    ) -> None:
        pass  # exact distances: no baselines to measure


MODEL = IrModel(
    name="cone",
    summary="exact cones (V-REP's model)",
    has_response=False,
    build=ConeModel,
)
