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
#: Cell size (m) of the grid that finds the track segments near a robot.
GRID_CELL = 0.02


def luminance(colour: Colour) -> float:
    """Brightness 0..1 of an RGB colour (Rec. 601 luma)."""
    r, g, b = colour
    return (0.299 * r + 0.587 * g + 0.114 * b) / 255.0


def _segment_distance_each(
    point: FloatArray, seg_start: FloatArray, seg_vector: FloatArray
) -> FloatArray:
    """Squared distance from one point to each of S segments."""
    length2 = np.maximum((seg_vector * seg_vector).sum(axis=1), 1e-300)
    w = point - seg_start
    s = np.clip((w * seg_vector).sum(axis=1) / length2, 0.0, 1.0)
    q = w - s[:, None] * seg_vector
    return (q * q).sum(axis=1)


class _Near:
    """Track segments prepared for the ground-sensor distance query.

    Points and segments are complex numbers (x + iy): the point–segment distance then
    takes half as many numpy calls, and at a few hundred elements the calls, not the
    arithmetic, are what cost.
    """

    __slots__ = ("count", "inv_len2", "start", "vector", "vector_conj")

    def __init__(self, seg_start: FloatArray, seg_vector: FloatArray) -> None:
        self.count = int(seg_start.shape[0])
        self.start = (seg_start[:, 0] + 1j * seg_start[:, 1])[None, :]
        self.vector = (seg_vector[:, 0] + 1j * seg_vector[:, 1])[None, :]
        self.vector_conj = self.vector.conj()
        len2 = (self.vector * self.vector_conj).real
        self.inv_len2 = 1.0 / np.where(len2 > 0.0, len2, 1.0)


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
        self._cell_segments: dict[tuple[int, int], npt.NDArray[np.intp]] = {}
        self._near_cache: dict[tuple[tuple[int, int], ...], _Near] = {}
        self._all = _Near(self.seg_start, self.seg_vector)

    # -- ground sensors --------------------------------------------------------------------
    def coverage(self, points: FloatArray, near: _Near | None = None) -> FloatArray:
        """Fraction (0..1) of each sensor footprint centred at ``points`` on the line.

        ``points`` is P×2 (x, y), or P complex numbers x + iy.

        ``near`` (from :meth:`segments_near`) limits the search to the segments that can
        matter; without it every segment of the track is tested.
        """
        if near is None:
            near = self._all
        if near.count == 0:
            return np.zeros(points.shape[0])
        if points.dtype.kind != "c":
            points = points[:, 0] + 1j * points[:, 1]
        w = points[:, None] - near.start  # P×S
        t = (w * near.vector_conj).real
        t *= near.inv_len2
        np.clip(t, 0.0, 1.0, out=t)
        w -= t * near.vector
        d = np.abs(w).min(axis=1)
        # covered length of the footprint strip [d - rho, d + rho] inside [-h, h]
        overlap = np.minimum(d + self.footprint, self.half_width)
        overlap -= np.maximum(d - self.footprint, -self.half_width)
        overlap *= 1.0 / (2.0 * self.footprint)
        return np.clip(overlap, 0.0, 1.0, out=overlap)

    def brightness(self, points: FloatArray, near: _Near | None = None) -> FloatArray:
        """Noise-free ground reading 0..1 at ``points`` (P×2); ``near`` as in :meth:`coverage`."""
        c = self.coverage(points, near)
        c *= self.line_brightness - self.floor_brightness
        c += self.floor_brightness
        return c

    def segments_near(self, centres: list[tuple[float, float]], reach: float) -> _Near:
        """The track segments that can lie within ``reach`` (m) of any of ``centres``.

        A track can have hundreds of segments, and measuring the distance to all of them
        for every ground sensor every step would cost more than the rest of the step.
        The floor is divided into cells of :data:`GRID_CELL`; each cell's candidate
        segments are found once (the first time a robot is in it) and the union for the
        robots' current cells is cached, so a step usually costs one dictionary lookup.
        ``reach`` must stay the same between calls (the world passes the centroid of each
        robot's ground sensors and their largest distance from it).
        """
        inv = 1.0 / GRID_CELL
        key = tuple((int(np.floor(x * inv)), int(np.floor(y * inv))) for x, y in centres)
        found = self._near_cache.get(key)
        if found is not None:
            return found
        idx = np.unique(np.concatenate([self._segments_in_cell(c, reach) for c in key]))
        found = _Near(self.seg_start[idx], self.seg_vector[idx])
        if len(self._near_cache) > 4096:
            self._near_cache.clear()
        self._near_cache[key] = found
        return found

    def _segments_in_cell(self, cell: tuple[int, int], reach: float) -> npt.NDArray[np.intp]:
        idx = self._cell_segments.get(cell)
        if idx is None:
            centre = (np.array(cell, dtype=float) + 0.5) * GRID_CELL
            # anything within reach of any point of the cell, plus the line's half-width and
            # the footprint, can touch a sensor of a robot whose centre is in the cell
            limit = GRID_CELL * np.sqrt(0.5) + reach + self.half_width + self.footprint
            if self.seg_start.shape[0]:
                d = np.sqrt(_segment_distance_each(centre, self.seg_start, self.seg_vector))
                idx = np.nonzero(d <= limit)[0]
            else:
                idx = np.zeros(0, dtype=np.intp)
            self._cell_segments[cell] = idx
        return idx

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
