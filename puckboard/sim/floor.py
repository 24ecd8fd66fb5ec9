"""The floor: a light surface with a dark line, as the ground sensors and the camera see it.

Ground sensors (:meth:`Floor.brightness`) are computed analytically from the distance to
the line's polyline, with a small sensor *footprint*: a real reflective sensor (a TCRT
or CNY70 a few millimetres above the floor) integrates light over a spot a few
millimetres wide, so its reading falls off over a few millimetres as it crosses the
line's edge instead of jumping. Modelling the spot as a uniform strip of half-width
``footprint`` across the line gives the covered fraction in closed form (no sampling
grid, no image resolution to choose) and makes the reading a continuous function of the
pose, which keeps line followers from chattering on a pixel boundary. Enki blurs its
floor image with a Gaussian (σ = 4 mm) for the same reason; ARGoS samples one point, and
so does a pixel of V-REP's light sensor: a footprint of 0 reads the line's brightness
wherever the point lies on the line and the floor's elsewhere. Each robot's profile says
its ``ground_footprint``; :data:`DEFAULT_FOOTPRINT` is for callers that name none.

Brightness is the colour's luminance (Rec. 601 weights) on a 0..1 scale, so the default
light floor reads ≈ 0.92 (raw ≈ 940 of 1023, close to the 900 that Webots' line example
calls white) and the default dark line ≈ 0.08. A track's ``contrast`` below 1 moves the
line's brightness towards the floor's (``--set surface.line_contrast``).

The camera needs the line's colour at a thousand floor points per frame; for it the line
is rasterised once (:meth:`Floor.on_line`) at 2 mm per cell, finer than any camera pixel
projected on the floor at the e-puck's resolutions.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Literal

import numpy as np
import numpy.typing as npt

from ..geometry import project_on_segments
from ..scenario.scene import Colour, Scene

__all__ = ["Floor", "luminance"]

FloatArray = npt.NDArray[np.float64]

#: Half-width (m) of a ground sensor's footprint across the line, where none is given
#: (the physical profiles' own value, puckboard.profile).
DEFAULT_FOOTPRINT = 0.002
#: Cell size (m) of the camera's line raster.
RASTER_CELL = 0.002
#: Cell size (m) of the grid that finds the track segments near a robot.
GRID_CELL = 0.02

# how brightness_values reads a set of footprints (see Floor._plan_ramps)
_RampPlan = Literal[False] | tuple[float, float] | list[tuple[float, float] | None]


def _check_footprint(footprint: float) -> None:
    if not 0.0 <= footprint < 0.05:
        raise ValueError(
            f"ground sensor footprint must lie in [0, 0.05) m (0: a point sample), got {footprint}"
        )


def luminance(colour: Colour) -> float:
    """Brightness 0..1 of an RGB colour (Rec. 601 luma)."""
    r, g, b = colour
    return (0.299 * r + 0.587 * g + 0.114 * b) / 255.0


def _towards(floor: Colour, line: Colour, share: float) -> Colour:
    """The colour ``share`` of the way from ``floor`` to ``line``, channel by channel."""
    r, g, b = (round(f + share * (c - f)) for f, c in zip(floor, line))
    return (r, g, b)


class _Near:
    """Track segments prepared for the ground-sensor distance query.

    Segments lie along the first axis (S×1 columns) and points along the second, so
    each point's nearest segment is a minimum over the first axis: an elementwise
    minimum of a few rows, cheaper than a minimum over a short last axis. The squared
    lengths' reciprocals are kept: a query multiplies by them.
    """

    __slots__ = ("ax", "ay", "count", "ex", "ey", "inv_len2")

    def __init__(self, seg_start: FloatArray, seg_vector: FloatArray) -> None:
        self.count = int(seg_start.shape[0])
        self.ax = seg_start[:, 0:1].copy()
        self.ay = seg_start[:, 1:2].copy()
        self.ex = seg_vector[:, 0:1].copy()
        self.ey = seg_vector[:, 1:2].copy()
        len2 = self.ex * self.ex + self.ey * self.ey
        self.inv_len2 = 1.0 / np.where(len2 > 0.0, len2, 1.0)

    def take(self, index: npt.NDArray[np.intp]) -> _Near:
        """The segments at ``index`` (repeats do no harm to a minimum), values unchanged."""
        subset = object.__new__(_Near)
        subset.count = int(index.shape[0])
        subset.ax = self.ax[index]
        subset.ay = self.ay[index]
        subset.ex = self.ex[index]
        subset.ey = self.ey[index]
        subset.inv_len2 = self.inv_len2[index]
        return subset


#: A grid: each cell's segments; and the segments already joined for sets of cells.
_Grid = dict[tuple[int, int], list[int]]
_Joined = dict[tuple[tuple[int, int], ...], _Near]
#: Grids of the tracks last built (see Floor.segments_near), by the track's geometry and
#: the grid's reach: the worlds of a sweep or a test session share their scene's track,
#: and building one was most of what making a world cost.
_GRIDS: dict[tuple[bytes, bytes, float, float], tuple[_Grid, _Joined]] = {}
#: Tracks whose grids are kept.
GRIDS_KEPT = 8


class Floor:
    """Floor brightness and line raster of one scene; all static data precomputed."""

    def __init__(self, scene: Scene, *, footprint: float = DEFAULT_FOOTPRINT) -> None:
        _check_footprint(footprint)
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
            if track.contrast != 1.0:
                # a line that looks less dark than its colour (glossy or worn tape, a
                # grey floor): its brightness moved towards the floor's, for the ground
                # sensors and the camera alike (only then: 1 keeps today's numbers exact)
                self.line_brightness = self.floor_brightness - track.contrast * (
                    self.floor_brightness - self.line_brightness
                )
                self.line_colour = _towards(scene.floor_colour, track.colour, track.contrast)
        self._raster: npt.NDArray[np.bool_] | None = None  # built when a camera first needs it
        self._origin = np.zeros(2)
        self._all = _Near(self.seg_start, self.seg_vector)
        self._grid_reach = -1.0
        self._grid: _Grid = {}
        self._joined: _Joined = {}
        self._ramps_of: dict[tuple[float, ...], _RampPlan] = {}

    def ramp(self, footprint: float) -> tuple[float, float] | None:
        """(slope, offset) of the reading ``offset + slope·d`` between the line's and the
        floor's brightness for a sensor of ``footprint`` at distance d from the line's
        centre (clamped to those two), or None for a point sample (footprint 0)."""
        if footprint == 0.0:
            return None
        contrast = self.floor_brightness - self.line_brightness
        slope = contrast / (2.0 * footprint)
        return slope, self.floor_brightness - contrast * (self.half_width + footprint) / (
            2.0 * footprint
        )

    def _affine(self, footprint: float) -> bool:
        """Whether a footprint's reading is the clamped ramp (the usual case): the line at
        least as wide as the footprint and darker than the floor."""
        return self.half_width >= footprint and self.line_brightness < self.floor_brightness

    # -- ground sensors --------------------------------------------------------------------
    def line_distance(self, points: FloatArray, near: _Near | None = None) -> FloatArray:
        """Distance (m) from each point to the line's centre polyline (``inf`` if no track).

        ``points`` is P×2 (x, y), or P complex numbers x + iy. ``near`` (from
        :meth:`segments_near`) limits the search to the segments that can matter;
        without it every segment of the track is tested.
        """
        if near is None:
            near = self._all
        if points.dtype.kind == "c":
            px, py = points.real, points.imag
        else:
            px, py = points[:, 0], points[:, 1]
        if near.count == 0:
            return np.full(points.shape[0], np.inf)
        _, qx, qy = project_on_segments(
            px[None, :] - near.ax,
            py[None, :] - near.ay,
            near.ex,
            near.ey,
            inv_len2=near.inv_len2,
        )  # S×P
        d = np.hypot(qx, qy)
        return d[0] if near.count == 1 else d.min(axis=0)  # type: ignore[no-any-return]

    def coverage(
        self, points: FloatArray, near: _Near | None = None, footprint: float | None = None
    ) -> FloatArray:
        """Fraction (0..1) of each sensor footprint centred at ``points`` on the line
        (``footprint`` default :attr:`footprint`; 0: 1 on the line, else 0)."""
        rho = self.footprint if footprint is None else footprint
        d = self.line_distance(points, near)
        if rho == 0.0:
            return (d <= self.half_width).astype(float)
        # covered length of the footprint strip [d - rho, d + rho] inside [-h, h]
        overlap = np.minimum(d + rho, self.half_width)
        overlap -= np.maximum(d - rho, -self.half_width)
        overlap *= 1.0 / (2.0 * rho)
        np.maximum(overlap, 0.0, out=overlap)
        return np.minimum(overlap, 1.0, out=overlap)

    def brightness(
        self, points: FloatArray, near: _Near | None = None, footprint: float | None = None
    ) -> FloatArray:
        """Noise-free ground reading 0..1 at ``points``; ``near`` as in :meth:`line_distance`,
        ``footprint`` as in :meth:`coverage`.

        When the line is at least as wide as the footprint (the usual case), the covered
        fraction is ``clip((h + ρ − d) / 2ρ, 0, 1)``, so the reading is an affine function
        of the distance d clamped between the line's and the floor's brightness: four
        numpy calls instead of a dozen.
        """
        rho = self.footprint if footprint is None else footprint
        ramp = self.ramp(rho)
        if ramp is None or not self._affine(rho):
            c = self.coverage(points, near, rho)
            c *= self.line_brightness - self.floor_brightness
            c += self.floor_brightness
            return c
        if near is not None and near.count == 0:
            # no segment near any point: the distance is infinite and the reading is
            # exactly the floor's, which the clamped line below would also give
            return np.full(points.shape[0], self.floor_brightness)
        d = self.line_distance(points, near)
        d *= ramp[0]
        d += ramp[1]
        np.maximum(d, self.line_brightness, out=d)
        return np.minimum(d, self.floor_brightness, out=d)

    def brightness_values(
        self,
        points: FloatArray,
        near: _Near | None = None,
        footprints: Sequence[float] | None = None,
    ) -> list[float]:
        """:meth:`brightness` as plain floats, for the handful of points a world senses,
        each point with its own footprint (``footprints``, one per point; default
        :attr:`footprint` for all).

        The affine reading and its two clamps are three float operations per point: on
        six ground sensors, four numpy calls cost more than doing them in Python. The
        operations and their order are those of :meth:`brightness`, so are the results.
        """
        if footprints is None:
            footprints = (self.footprint,) * points.shape[0]
        plan = self._ramps_of.get(tuple(footprints))
        if plan is None:
            plan = self._plan_ramps(footprints)
        if plan is False:  # a line narrower than a spot: the general coverage, one by one
            return [
                float(self.brightness(points[k : k + 1], near, f)[0])
                for k, f in enumerate(footprints)
            ]
        if near is not None and near.count == 0:
            return [self.floor_brightness] * points.shape[0]
        low, high = self.line_brightness, self.floor_brightness
        distances = self.line_distance(points, near).tolist()
        if isinstance(plan, tuple):  # one footprint for every point (the usual case)
            slope, offset = plan
            values = []
            for d in distances:
                v = d * slope + offset
                v = low if v < low else v
                values.append(high if v > high else v)
            return values
        h = self.half_width
        values = []
        for d, ramp in zip(distances, plan):
            if ramp is None:  # a point sample
                values.append(low if d <= h else high)
                continue
            v = d * ramp[0] + ramp[1]
            v = low if v < low else v
            values.append(high if v > high else v)
        return values

    def _plan_ramps(self, footprints: Sequence[float]) -> _RampPlan:
        """How :meth:`brightness_values` reads points of these footprints: False (the
        general coverage), one (slope, offset) for all, or one ramp (None: a point
        sample) per point."""
        plan: _RampPlan
        if not all(self._affine(f) for f in footprints):
            plan = False
        elif len(set(footprints)) == 1 and footprints[0] > 0.0:
            ramp = self.ramp(footprints[0])
            assert ramp is not None  # a footprint above 0 has a ramp
            plan = ramp
        else:
            plan = [self.ramp(f) for f in footprints]
        self._ramps_of[tuple(footprints)] = plan
        return plan

    def segments_near(
        self, centres: list[tuple[float, float]], reach: float, footprint: float | None = None
    ) -> _Near:
        """Track segments that include every segment within ``reach`` (m) of ``centres``.

        A track can have hundreds of segments, and measuring the distance to all of them
        for every ground sensor every step would cost more than the rest of the step.
        So the floor is divided into cells of :data:`GRID_CELL` and each segment is
        listed in every cell its bounding box (grown by ``reach``, the line's half-width
        and the footprint) overlaps; a step then only looks up each robot's cell. The
        lists are a superset of what can matter, so readings are exactly those of a
        search over all segments. ``reach`` is the largest distance of a ground sensor
        from the point passed in ``centres`` (the world passes the centroid of each
        robot's ground sensors), ``footprint`` the largest footprint read there
        (default :attr:`footprint`).
        """
        grow = reach + (self.footprint if footprint is None else footprint)
        if grow != self._grid_reach:
            self._build_grid(grow)
        inv = 1.0 / GRID_CELL
        key = tuple([(math.floor(x * inv), math.floor(y * inv)) for x, y in centres])
        joined = self._joined.get(key)
        if joined is not None:
            return joined
        # every cell's segments, picked from the whole track's prepared arrays in one
        # fancy index per array (the values are those of the track, so a reading does
        # not depend on which cells were joined)
        grid = self._grid
        index: list[int] = []
        for cell in key:
            index += grid.get(cell, ())
        joined = self._all.take(np.array(index, dtype=np.intp))
        if len(self._joined) > 4096:
            self._joined.clear()
        self._joined[key] = joined
        return joined

    def _build_grid(self, reach: float) -> None:
        key = (self.seg_start.tobytes(), self.seg_vector.tobytes(), self.half_width, reach)
        kept = _GRIDS.get(key)
        if kept is None:
            if len(_GRIDS) >= GRIDS_KEPT:
                del _GRIDS[next(iter(_GRIDS))]  # the oldest
            kept = _GRIDS[key] = (self._grid_cells(reach), {})
        self._grid, self._joined = kept
        self._grid_reach = reach

    def _grid_cells(self, reach: float) -> _Grid:
        """Each grid cell's segments: those whose bounding box, grown by ``reach`` and
        the line's half-width, overlaps the cell."""
        grow = reach + self.half_width
        grid: _Grid = {}
        inv = 1.0 / GRID_CELL
        ends = self.seg_start + self.seg_vector
        lo = np.floor((np.minimum(self.seg_start, ends) - grow) * inv).astype(int).tolist()
        hi = np.floor((np.maximum(self.seg_start, ends) + grow) * inv).astype(int).tolist()
        for k, ((i0, j0), (i1, j1)) in enumerate(zip(lo, hi)):
            for i in range(i0, i1 + 1):
                for j in range(j0, j1 + 1):
                    grid.setdefault((i, j), []).append(k)
        return grid

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
        # sample the centre line every cell, then mark every cell whose centre lies
        # within the half-width of a sample: one vectorised pass instead of one per segment
        lengths = np.hypot(self.seg_vector[:, 0], self.seg_vector[:, 1])
        counts = np.maximum(np.ceil(lengths / RASTER_CELL).astype(int), 1) + 1
        seg = np.repeat(np.arange(len(counts)), counts)
        t = np.concatenate([np.linspace(0.0, 1.0, c) for c in counts])
        pts = self.seg_start[seg] + t[:, None] * self.seg_vector[seg]
        k = int(np.ceil(self.half_width / RASTER_CELL)) + 1
        offsets = np.arange(-k, k + 1)
        di, dj = (a.ravel() for a in np.meshgrid(offsets, offsets, indexing="ij"))
        base = np.floor((pts - lo) / RASTER_CELL).astype(np.intp)
        ci = base[:, 0:1] + di  # P×K
        cj = base[:, 1:2] + dj
        dx = lo[0] + (ci + 0.5) * RASTER_CELL - pts[:, 0:1]
        dy = lo[1] + (cj + 0.5) * RASTER_CELL - pts[:, 1:2]
        hit = dx * dx + dy * dy <= self.half_width * self.half_width
        ci = np.clip(ci[hit], 0, raster.shape[0] - 1)
        cj = np.clip(cj[hit], 0, raster.shape[1] - 1)
        raster[ci, cj] = True
        self._raster = raster
        self._origin = lo

    def on_line(self, x: FloatArray, y: FloatArray) -> npt.NDArray[np.bool_]:
        """Whether floor points (any shape, m) lie on the line, from the 2 mm raster."""
        if self._raster is None:
            self._build_raster()
        raster = self._raster
        assert raster is not None
        i = ((x - self._origin[0]) * (1.0 / RASTER_CELL)).astype(np.intp)
        j = ((y - self._origin[1]) * (1.0 / RASTER_CELL)).astype(np.intp)
        nx, ny = raster.shape
        inside = (i >= 0) & (i < nx) & (j >= 0) & (j < ny)
        np.clip(i, 0, nx - 1, out=i)
        np.clip(j, 0, ny - 1, out=j)
        return raster[i, j] & inside
