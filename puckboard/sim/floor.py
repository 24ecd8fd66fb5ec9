"""The floor: a light surface with a dark line, as the ground sensors and the camera see it.

Ground sensors (:meth:`Floor.brightness`) are computed analytically from the distance to
the line's polyline, with a small sensor *footprint*: a real reflective sensor (a TCRT
or CNY70 a few millimetres above the floor) integrates light over a spot a few
millimetres wide, so its reading falls off over a few millimetres as it crosses the
line's edge instead of jumping. Modelling the spot as a uniform strip of half-width
``footprint`` across the line gives the covered fraction in closed form (no sampling
grid, no image resolution to choose) and makes the reading a continuous function of the
pose, which keeps line followers from chattering on a pixel boundary. Enki blurs its
floor image with a Gaussian (σ = 4 mm) for the same reason; ARGoS samples one point.

Brightness is the colour's luminance (Rec. 601 weights) on a 0..1 scale, so the default
light floor reads ≈ 0.92 (raw ≈ 940 of 1023, close to the 900 that Webots' line example
calls white) and the default dark line ≈ 0.08.

The camera needs the line's colour at a thousand floor points per frame; for it the line
is rasterised once (:meth:`Floor.on_line`) at 2 mm per cell, finer than any camera pixel
projected on the floor at the e-puck's resolutions.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from .geometry import segment_distance
from .scene import Colour, Scene

__all__ = ["Floor", "luminance"]

FloatArray = npt.NDArray[np.float64]

#: Half-width (m) of a ground sensor's footprint across the line.
DEFAULT_FOOTPRINT = 0.002
#: Cell size (m) of the camera's line raster.
RASTER_CELL = 0.002


def luminance(colour: Colour) -> float:
    """Brightness 0..1 of an RGB colour (Rec. 601 luma)."""
    r, g, b = colour
    return (0.299 * r + 0.587 * g + 0.114 * b) / 255.0


class Floor:
    """Floor brightness and line raster of one scene; all static data precomputed."""

    def __init__(self, scene: Scene, *, footprint: float = DEFAULT_FOOTPRINT) -> None:
        if footprint <= 0:
            raise ValueError(f"ground sensor footprint must be positive metres, got {footprint}")
        self.footprint = footprint
        self.floor_colour = scene.floor_colour
        self.floor_brightness = luminance(scene.floor_colour)
        track = scene.track
        if track is None:
            self.seg_start = np.zeros((0, 2))
            self.seg_vector = np.zeros((0, 2))
            self.half_width = 0.0
            self.line_colour: Colour = scene.floor_colour
            self.line_brightness = self.floor_brightness
        else:
            seg = track.segments()
            self.seg_start = np.ascontiguousarray(seg[:, 0])
            self.seg_vector = np.ascontiguousarray(seg[:, 1] - seg[:, 0])
            self.half_width = track.width / 2.0
            self.line_colour = track.colour
            self.line_brightness = luminance(track.colour)
        self._build_raster()

    # -- ground sensors --------------------------------------------------------------------
    def coverage(self, points: FloatArray) -> FloatArray:
        """Fraction (0..1) of each sensor footprint centred at ``points`` (P×2) on the line."""
        if self.seg_start.shape[0] == 0:
            return np.zeros(points.shape[0])
        d = segment_distance(points, self.seg_start, self.seg_vector)
        rho = self.footprint
        h = self.half_width
        overlap = np.minimum(d + rho, h) - np.maximum(d - rho, -h)
        return np.clip(overlap / (2.0 * rho), 0.0, 1.0)

    def brightness(self, points: FloatArray) -> FloatArray:
        """Noise-free ground reading 0..1 at ``points`` (P×2)."""
        c = self.coverage(points)
        return self.floor_brightness + c * (self.line_brightness - self.floor_brightness)

    # -- camera ----------------------------------------------------------------------------
    def _build_raster(self) -> None:
        if self.seg_start.shape[0] == 0:
            self._raster = np.zeros((1, 1), dtype=bool)
            self._origin = np.zeros(2)
            return
        ends = self.seg_start + self.seg_vector
        pts = np.vstack([self.seg_start, ends])
        pad = self.half_width + 2 * RASTER_CELL
        lo = pts.min(axis=0) - pad
        hi = pts.max(axis=0) + pad
        shape = np.ceil((hi - lo) / RASTER_CELL).astype(int) + 1  # (nx, ny)
        raster = np.zeros((int(shape[0]), int(shape[1])), dtype=bool)
        for a, e in zip(self.seg_start, self.seg_vector):
            b = a + e
            i0, j0 = np.floor((np.minimum(a, b) - pad - lo) / RASTER_CELL).astype(int)
            i1, j1 = np.ceil((np.maximum(a, b) + pad - lo) / RASTER_CELL).astype(int)
            i0, j0 = max(i0, 0), max(j0, 0)
            i1, j1 = min(i1, raster.shape[0] - 1), min(j1, raster.shape[1] - 1)
            xs = lo[0] + (np.arange(i0, i1 + 1) + 0.5) * RASTER_CELL
            ys = lo[1] + (np.arange(j0, j1 + 1) + 0.5) * RASTER_CELL
            gx, gy = np.meshgrid(xs, ys, indexing="ij")
            cells = np.column_stack([gx.ravel(), gy.ravel()])
            near = segment_distance(cells, a[None, :], e[None, :]) <= self.half_width
            raster[i0 : i1 + 1, j0 : j1 + 1] |= near.reshape(gx.shape)
        self._raster = raster
        self._origin = lo

    def on_line(self, x: FloatArray, y: FloatArray) -> npt.NDArray[np.bool_]:
        """Whether floor points (any shape, m) lie on the line, from the 2 mm raster."""
        i = ((x - self._origin[0]) * (1.0 / RASTER_CELL)).astype(np.intp)
        j = ((y - self._origin[1]) * (1.0 / RASTER_CELL)).astype(np.intp)
        nx, ny = self._raster.shape
        inside = (i >= 0) & (i < nx) & (j >= 0) & (j < ny)
        np.clip(i, 0, nx - 1, out=i)
        np.clip(j, 0, ny - 1, out=j)
        return self._raster[i, j] & inside
