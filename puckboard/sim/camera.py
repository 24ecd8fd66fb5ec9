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
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from .floor import Floor
from .geometry import cast_rays

__all__ = ["BACKGROUND", "CAMERA_FORWARD", "MAX_VIEW", "CameraRenderer"]

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
    ) -> None:
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
        self.floor_rows = slice(int(floor_rows[0]), height) if len(floor_rows) else slice(0, 0)
        v = self.row_v[self.floor_rows]  # F×1
        depth = focal * camera_height / v  # forward distance of each floor row (m)
        self.floor_fwd = np.broadcast_to(depth, (len(v), width)).copy()  # F×W
        self.floor_left = depth * lateral[None, :]
        self.floor_far = self.floor_fwd > MAX_VIEW
        fc = np.array(floor.floor_colour, dtype=np.uint8)
        lc = np.array(floor.line_colour, dtype=np.uint8)
        self._floor_colour = fc
        self._line_colour = lc
        self._background = np.array(BACKGROUND, dtype=np.uint8)

    def render(
        self,
        x: float,
        y: float,
        theta: float,
        seg_start: FloatArray,
        seg_vector: FloatArray,
        circle_centres: FloatArray,
        circle_radii: FloatArray,
        colours: npt.NDArray[np.uint8],
        heights: FloatArray,
        ignore_circle: int = -1,
    ) -> npt.NDArray[np.uint8]:
        """An upright H×W×3 uint8 image from a robot at (x, y, theta).

        ``colours`` and ``heights`` describe the hit objects in :func:`cast_rays` order
        (segments, then circles); ``ignore_circle`` is the robot's own body.
        """
        c, s = math.cos(theta), math.sin(theta)
        cx = x + CAMERA_FORWARD * c
        cy = y + CAMERA_FORWARD * s
        angles = theta + self.col_angle
        dirs = np.column_stack([np.cos(angles), np.sin(angles)])
        origins = np.broadcast_to(np.array([cx, cy]), (self.width, 2))
        ignore = None
        if ignore_circle >= 0:
            ignore = np.zeros((self.width, circle_centres.shape[0]), dtype=bool)
            ignore[:, ignore_circle] = True
        dist, hit = cast_rays(
            origins, dirs, MAX_VIEW, seg_start, seg_vector, circle_centres, circle_radii, ignore
        )
        depth = dist * self.col_cos  # inf where nothing was hit
        seen = hit >= 0
        with np.errstate(divide="ignore", invalid="ignore"):
            v_bottom = np.where(seen, self.focal * self.camera_height / depth, np.inf)
            v_top = np.where(
                seen, -self.focal * (heights[hit] - self.camera_height) / depth, np.inf
            )
        image = np.empty((self.height, self.width, 3), dtype=np.uint8)
        image[:] = self._background
        # floor: world coordinates of each floor pixel, then the line raster
        fx = cx + self.floor_fwd * c - self.floor_left * s
        fy = cy + self.floor_fwd * s + self.floor_left * c
        on_line = self.floor.on_line(fx, fy)
        floor_img = np.where(on_line[..., None], self._line_colour, self._floor_colour)
        floor_img[self.floor_far] = self._background
        image[self.floor_rows] = floor_img
        # objects: from their foot on the floor up to their top edge
        v = self.row_v
        covered = (v >= v_top[None, :]) & (v <= v_bottom[None, :])
        obj_colour = colours[np.where(seen, hit, 0)]  # W×3
        np.copyto(
            image, np.broadcast_to(obj_colour[None, :, :], image.shape), where=covered[..., None]
        )
        return image
