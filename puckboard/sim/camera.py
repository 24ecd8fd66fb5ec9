"""The e-puck's forward camera, rendered from the 2D world by column ray casting.

The world is flat with upright extruded shapes, so one ray per image column finds what
that column sees (the technique of 1990s "2.5D" renderers): the nearest obstacle, robot
or wall along the column's bearing, drawn from the floor up to its height with the usual
pinhole projection, so nearer things look taller; below it the floor (light, with the
dark line), above it a plain background. Perpendicular depth (ray length × cos of the
column's angle) is used, so straight walls stay straight.

Mounting follows Webots' e-puck: 3 cm ahead of the axle, 2.8 cm above the floor
(:attr:`RobotProfile.camera_height`), horizontal field of view
:attr:`RobotProfile.camera_fov` (0.84 rad), square pixels. The image is upright (row 0
at the top) and noise-free, so rendering never touches the simulation's random numbers.

A frame is a few dozen numpy calls on arrays of W rays and (H/2)×W floor pixels.
:class:`RobotCameras` keeps one renderer per image size and camera model of a world, so
what a renderer prepares once (column angles, floor rows, the palette) is prepared once.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from ..profile import RobotProfile
from .floor import Floor
from .geometry import cast_rays
from .surfaces import Surfaces

__all__ = ["BACKGROUND", "CAMERA_FORWARD", "MAX_VIEW", "CameraRenderer", "RobotCameras"]

FloatArray = npt.NDArray[np.float64]

#: Camera position ahead of the robot's axle (m), as in Webots' e-puck model.
CAMERA_FORWARD = 0.03
#: Farther than this (m) nothing is drawn: the background shows.
MAX_VIEW = 5.0
#: Colour above the horizon and beyond the view distance (a pale room wall).
BACKGROUND = (196, 204, 214)


class CameraRenderer:
    """Renders W×H images for one camera model; static data is prepared once."""

    def __init__(
        self,
        floor: Floor,
        *,
        width: int,
        height: int,
        fov: float,
        camera_height: float,
        object_colours: npt.NDArray[np.uint8],
        object_heights: FloatArray,
    ) -> None:
        """``object_colours`` (K×3) and ``object_heights`` (K, m) describe what a ray can
        hit, in :func:`cast_rays` order: segments first, then circles."""
        if width < 1 or height < 1:
            raise ValueError(f"camera size must be positive pixels, got {width}×{height}")
        if not 0 < fov < math.pi:
            raise ValueError(f"camera field of view must lie in (0, π) rad, got {fov}")
        self.floor = floor
        self.width = width
        self.height = height
        self.camera_height = camera_height
        focal = (width / 2.0) / math.tan(fov / 2.0)
        self.focal = focal
        # column c looks at angle alpha_c, positive to the left (image left = robot left)
        lateral = (width / 2.0 - (np.arange(width) + 0.5)) / focal  # tan(alpha)
        self.col_angle = np.arctan(lateral)
        self.col_cos = np.cos(self.col_angle)
        # row offsets below the image centre (pixels, positive downwards)
        self.row_v = (np.arange(height) + 0.5 - height / 2.0)[:, None]  # H×1
        floor_rows = np.nonzero(self.row_v[:, 0] > 0)[0]
        self.first_floor_row = int(floor_rows[0]) if len(floor_rows) else height
        v = self.row_v[self.first_floor_row :]  # F×1
        depth = focal * camera_height / v  # forward distance of each floor row (m)
        self.floor_fwd = np.broadcast_to(depth, (len(v), width)).copy()  # F×W
        self.floor_left = depth * lateral[None, :]
        self.floor_far = self.floor_fwd > MAX_VIEW
        # every pixel is an index into one palette: background, floor, line, objects
        self.palette = np.vstack(
            [
                np.array([BACKGROUND, floor.floor_colour, floor.line_colour], dtype=np.uint8),
                np.asarray(object_colours, dtype=np.uint8).reshape(-1, 3),
            ]
        )
        self.object_heights = np.asarray(object_heights, dtype=float)
        self._index = np.zeros((height, width), dtype=np.intp)
        self._columns = np.arange(width)

    def render(
        self,
        x: float,
        y: float,
        theta: float,
        seg_start: FloatArray,
        seg_vector: FloatArray,
        circle_centres: FloatArray,
        circle_radii: FloatArray,
        ignore_circle: int = -1,
    ) -> npt.NDArray[np.uint8]:
        """An upright H×W×3 uint8 image from a robot at (x, y, theta).

        ``ignore_circle`` is the robot's own body, which encloses the camera.
        """
        c, s = math.cos(theta), math.sin(theta)
        cx = x + CAMERA_FORWARD * c
        cy = y + CAMERA_FORWARD * s
        angles = theta + self.col_angle
        dirs = np.empty((self.width, 2))
        dirs[:, 0] = np.cos(angles)
        dirs[:, 1] = np.sin(angles)
        origins = np.empty_like(dirs)
        origins[:, 0] = cx
        origins[:, 1] = cy
        ignore = None
        if ignore_circle >= 0:
            ignore = np.zeros((self.width, circle_centres.shape[0]), dtype=bool)
            ignore[:, ignore_circle] = True
        dist, hit = cast_rays(
            origins, dirs, MAX_VIEW, seg_start, seg_vector, circle_centres, circle_radii, ignore
        )
        index = self._index
        index.fill(0)
        # floor: world coordinates of each floor pixel, then the line raster
        fx = cx + self.floor_fwd * c - self.floor_left * s
        fy = cy + self.floor_fwd * s + self.floor_left * c
        floor_index = index[self.first_floor_row :]
        floor_index[...] = self.floor.on_line(fx, fy)
        floor_index += 1
        floor_index[self.floor_far] = 0
        # objects: from their foot on the floor up to their top edge
        seen = hit >= 0
        if seen.any():
            with np.errstate(divide="ignore", invalid="ignore"):
                scale = self.focal / (dist * self.col_cos)  # pixels per metre at that depth
                v_bottom = np.where(seen, scale * self.camera_height, np.inf)
                v_top = np.where(
                    seen, -scale * (self.object_heights[hit] - self.camera_height), np.inf
                )
            covered = (self.row_v >= v_top) & (self.row_v <= v_bottom)
            np.copyto(index, (hit + 3)[None, :], where=covered)
        return self.palette[index]


class RobotCameras:
    """The cameras of a world's robots: a :class:`CameraRenderer` per image size and
    camera model (field of view, mounting height), made on first use."""

    def __init__(
        self,
        floor: Floor,
        surfaces: Surfaces,
        profiles: Sequence[RobotProfile],
        default_size: tuple[int, int],
    ) -> None:
        self.floor = floor
        self.surfaces = surfaces
        self.profiles = profiles
        self.default_size = default_size
        self._renderers: dict[tuple[int, int, float, float], CameraRenderer] = {}

    def render(
        self, i: int, poses: FloatArray, size: tuple[int, int] | None = None
    ) -> npt.NDArray[np.uint8]:
        """Robot ``i``'s image with every robot at ``poses`` (N×3); ``size`` = (width,
        height), the scene's by default."""
        width, height = size if size is not None else self.default_size
        profile = self.profiles[i]
        key = (int(width), int(height), profile.camera_fov, profile.camera_height)
        renderer = self._renderers.get(key)
        if renderer is None:
            renderer = CameraRenderer(
                self.floor,
                width=int(width),
                height=int(height),
                fov=profile.camera_fov,
                camera_height=profile.camera_height,
                object_colours=self.surfaces.object_colours,
                object_heights=self.surfaces.object_heights,
            )
            self._renderers[key] = renderer
        s = self.surfaces
        n_static = s.n_static_circles
        s.circle_centres[n_static:] = poses[:, :2]
        x, y, th = poses[i].tolist()
        return renderer.render(
            x,
            y,
            th,
            s.seg_start,
            s.seg_vector,
            s.circle_centres,
            s.circle_radii,
            ignore_circle=n_static + i,
        )
