"""The IR proximity sensors of every robot in a world, computed together once per step.

Each sensor casts ``rays`` rays spread over its aperture (see docs/simulator.md for why).
Casting them one by one from Python would cost tens of microseconds each, so all rays of
all robots are tested against every object near them in one set of numpy calls per step
(:func:`~puckboard.sim.geometry.segment_hits`, :func:`~puckboard.sim.geometry.circle_hits`), and
only when something is near: a conservative broad phase in plain Python (a few
microseconds) finds which robots can see anything and what they can see. Most steps of a
line-following run cast no ray at all.

Per sensor the model reports the nearest hit over its rays (V-REP's semantics: exactly
the range when nothing is seen) and a raw e-puck value, the Gaussian-weighted mean of the
rays' responses through the Webots table (:mod:`.ir`), with relative noise.
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..ir_response import _D, _RAW, _SIGMA, RAW_MAX, TABLE_RANGE, raw_from_distance, relative_sigma
from ..profile import RobotProfile
from .geometry import circle_hits, segment_hits

__all__ = ["PolygonBound", "ProximitySensors", "WallSegment"]

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class PolygonBound:
    """A polygon obstacle for the broad phase: bounding circle and its edges' indices."""

    x: float
    y: float
    radius: float
    segments: tuple[int, ...]


@dataclass(frozen=True)
class WallSegment:
    """An arena wall for the broad phase: tested exactly (walls are long)."""

    ax: float
    ay: float
    ex: float
    ey: float
    index: int


@dataclass(frozen=True)
class _Subset:
    """Rays and objects selected by one broad-phase outcome.

    Objects lie along the first axis of the cast (a column per coordinate, one row per
    segment or circle) and rays along the second, so the nearest hit of every ray is a
    minimum over the first axis: an elementwise minimum of a few rows, several times
    cheaper than a minimum over a short last axis.
    """

    robots: npt.NDArray[np.intp]
    local_origin: npt.NDArray[np.complex128]
    local_direction: npt.NDArray[np.complex128]
    visible: npt.NDArray[np.bool_]
    seg_ax: FloatArray
    seg_ay: FloatArray
    seg_ex: FloatArray
    seg_ey: FloatArray
    circles: tuple[int, ...]
    circle_radii_sq: FloatArray
    weights: FloatArray
    range_col: FloatArray
    every_robot: bool


class ProximitySensors:
    """IR sensor layout of N robots and the static things their rays can hit.

    ``seg_start``/``seg_vector`` are every static segment (polygon edges, walls);
    circles are the static round obstacles followed by one circle per robot (their
    centres are the poses passed to :meth:`sense` each step). ``polygons`` and ``walls`` say which
    segments belong to what, for the broad phase.
    """

    def __init__(
        self,
        profiles: Sequence[RobotProfile],
        *,
        rays: int,
        seg_start: FloatArray,
        seg_vector: FloatArray,
        static_circles: Sequence[tuple[float, float, float]],
        polygons: Sequence[PolygonBound],
        walls: Sequence[WallSegment],
    ) -> None:
        if rays < 1:
            raise ValueError(f"ir_rays must be at least 1, got {rays}")
        n = len(profiles)
        self.n = n
        self.rays = rays
        self.seg_start = seg_start
        self.seg_vector = seg_vector
        self.static_circles = tuple(static_circles)
        self.n_static = len(static_circles)
        self.polygons = tuple(polygons)
        self.walls = tuple(
            (w.ax, w.ay, w.ex, w.ey, w.ex * w.ex + w.ey * w.ey, w.index) for w in walls
        )
        self.robot_radii = [p.body_radius for p in profiles]
        # robots whose sensors are cones (V-REP's model) cast no rays: sim.cone computes them
        self.casts = [p.prox_model == "rays" for p in profiles]
        self.cones_near: list[int] = []
        self.circle_radii = np.array([c[2] for c in static_circles] + self.robot_radii, dtype=float)
        self.range = np.array([p.prox_range for p in profiles])[:, None]  # N×1
        self.cast_length = max(TABLE_RANGE, float(self.range.max()))

        origin_x = np.zeros((n, 8 * rays))
        origin_y = np.zeros((n, 8 * rays))
        angle = np.zeros((n, 8 * rays))
        weights = np.zeros((n, 8, rays))
        for i, p in enumerate(profiles):
            if len(p.prox_poses) != 8:
                raise ValueError(f"profile {p.name!r} must have 8 proximity sensor poses")
            half = p.prox_aperture / 2
            offsets = np.linspace(-half, half, rays) if rays > 1 else np.zeros(1)
            # Webots combines a sensor's rays with Gaussian weights; σ = aperture/4 puts
            # the outermost rays at two standard deviations.
            sigma = max(p.prox_aperture / 4.0, 1e-9)
            w = np.exp(-0.5 * (offsets / sigma) ** 2)
            for s, pose in enumerate(p.prox_poses):
                cols = slice(s * rays, (s + 1) * rays)
                origin_x[i, cols] = pose.x
                origin_y[i, cols] = pose.y
                angle[i, cols] = pose.heading + offsets
                weights[i, s] = w / w.sum()
        self._local_origin = origin_x + 1j * origin_y
        self._local_direction = np.exp(1j * angle)
        self._weights = weights
        # a robot's rays never see its own body (its sensors sit on or inside its outline)
        ignore = np.zeros((n, 8 * rays, self.n_static + n), dtype=bool)
        for i in range(n):
            ignore[i, :, self.n_static + i] = True
        self._ignore = ignore
        #: what a sensor reads when its rays hit nothing: the table's far baseline
        self.baseline_raw = (raw_from_distance(np.inf) * weights).sum(axis=2)
        # how far from a robot's centre its rays can reach
        offset = max(math.hypot(q.x, q.y) for p in profiles for q in p.prox_poses)
        self.reach = offset + self.cast_length
        # squared broad-phase limits, computed once
        reach = self.reach
        self._circle_bounds = tuple(
            (k, cx, cy, (reach + cr) * (reach + cr))
            for k, (cx, cy, cr) in enumerate(self.static_circles)
        )
        self._robot_lim2 = [(reach + r) * (reach + r) for r in self.robot_radii]
        self._polygon_bounds = tuple(
            (p.x, p.y, (reach + p.radius) * (reach + p.radius), p.segments) for p in self.polygons
        )
        self._cache: dict[tuple[tuple[int, ...], ...], _Subset] = {}
        self._far_sigma_noise = math.nan
        self._far_sigma_value = np.zeros((n, 8))

    # -- broad phase -----------------------------------------------------------------------
    def near(self, poses: Sequence[Sequence[float]]) -> tuple[list[int], list[int], list[int]]:
        """Which robots can see anything, and which circles and segments they may see.

        Conservative (bounding circles, exact wall distances), so it never drops a hit.
        Circle indices count static circles first, then robots.
        """
        reach2 = self.reach * self.reach
        robots: list[int] = []
        cones: list[int] = []
        circles: set[int] = set()
        segments: set[int] = set()
        n = self.n
        n_static = self.n_static
        # each robot pair's distance once: i may see j, and j may see i
        sees = [False] * n
        for i in range(n):
            xi, yi = poses[i][0], poses[i][1]
            for j in range(i + 1, n):
                dx, dy = xi - poses[j][0], yi - poses[j][1]
                d2 = dx * dx + dy * dy
                if d2 < self._robot_lim2[j]:
                    circles.add(n_static + j)
                    sees[i] = True
                if d2 < self._robot_lim2[i]:
                    circles.add(n_static + i)
                    sees[j] = True
        for i in range(n):
            x, y = poses[i][0], poses[i][1]
            found = sees[i]
            for k, cx, cy, lim2 in self._circle_bounds:
                dx, dy = x - cx, y - cy
                if dx * dx + dy * dy < lim2:
                    circles.add(k)
                    found = True
            for px, py, lim2, poly_segments in self._polygon_bounds:
                dx, dy = x - px, y - py
                if dx * dx + dy * dy < lim2:
                    segments.update(poly_segments)
                    found = True
            for ax, ay, ex, ey, len2, k in self.walls:
                wx, wy = x - ax, y - ay
                t = (wx * ex + wy * ey) / len2
                t = 0.0 if t < 0.0 else 1.0 if t > 1.0 else t
                qx, qy = wx - t * ex, wy - t * ey
                if qx * qx + qy * qy < reach2:
                    segments.add(k)
                    found = True
            if found:
                (robots if self.casts[i] else cones).append(i)
        #: robots without rays (V-REP's cone model) that have something within reach
        self.cones_near = cones
        return robots, sorted(circles), sorted(segments)

    def _subset(self, robots: list[int], circles: list[int], segments: list[int]) -> _Subset:
        """The static arrays for one broad-phase outcome, prepared once and cached.

        Which robots are near which objects changes only every few dozen steps, so the
        fancy indexing that selects their rays and objects is done once per combination.
        """
        key = (tuple(robots), tuple(circles), tuple(segments))
        prep = self._cache.get(key)
        if prep is None:
            idx = np.array(robots, dtype=np.intp)
            cidx = np.array(circles, dtype=np.intp)
            sidx = np.array(segments, dtype=np.intp)
            m = len(robots) * 8 * self.rays
            seg_start = self.seg_start[sidx].reshape(-1, 2)
            seg_vector = self.seg_vector[sidx].reshape(-1, 2)
            radii = self.circle_radii[cidx]
            prep = _Subset(
                robots=idx,
                local_origin=self._local_origin[idx],
                local_direction=self._local_direction[idx],
                # C×m: which circle each ray may see (never its own robot's body)
                visible=np.ascontiguousarray(
                    ~self._ignore[idx][:, :, cidx].reshape(m, len(cidx)).T
                ),
                seg_ax=seg_start[:, 0:1].copy(),
                seg_ay=seg_start[:, 1:2].copy(),
                seg_ex=seg_vector[:, 0:1].copy(),
                seg_ey=seg_vector[:, 1:2].copy(),
                circles=tuple(circles),
                circle_radii_sq=(radii * radii)[:, None],
                weights=self._weights[idx],
                range_col=self.range[idx],
                every_robot=len(robots) == self.n,
            )
            if len(self._cache) > 1024:
                self._cache.clear()
            self._cache[key] = prep
        return prep

    # -- the step --------------------------------------------------------------------------
    def sense(
        self,
        poses: Sequence[Sequence[float]],
        distance: FloatArray,
        raw: FloatArray,
        *,
        noise: float = 0.0,
        z: FloatArray | None = None,
    ) -> None:
        """Fill ``distance`` (N×8 m) and ``raw`` (N×8) for robots at ``poses`` (x, y, θ).

        The robots' bodies are circles at ``poses``. With ``noise`` > 0, ``z`` (N×8 standard normals) perturbs the readings: raw by the
        relative σ √(noise² + σ_table²), a seen distance by −½·noise·z (raw falls roughly
        as 1/d², so a high reading means "closer"); an empty reading stays at the range.
        """
        robots, circles, segments = self.near(poses)
        if noise <= 0:
            z = None
        if not robots:
            # Nothing near anyone (most steps of a line-following run): every sensor
            # reads the range and the far baseline, whose noise σ is fixed, so the
            # table look-ups and the "seen" test decide nothing and are skipped.
            distance[:] = self.range
            if z is not None:
                np.multiply(self._far_sigma(noise), z, out=raw)
                raw += 1.0
                raw *= self.baseline_raw
            else:
                raw[:] = self.baseline_raw
        else:
            prep = self._subset(robots, circles, segments)
            # rays as complex numbers: origin = position + rotation·local, direction =
            # rotation·local direction (fewer numpy calls than separate x and y)
            frames = np.array(
                [(complex(poses[i][0], poses[i][1]), cmath.exp(1j * poses[i][2])) for i in robots]
            )
            position = frames[:, 0:1]
            rotation = frames[:, 1:2]
            origin = (position + rotation * prep.local_origin).reshape(-1)
            direction = (rotation * prep.local_direction).reshape(-1)
            ox, oy, dx, dy = origin.real, origin.imag, direction.real, direction.imag
            hits = []
            if prep.seg_ax.shape[0]:
                hits.append(
                    segment_hits(ox, oy, dx, dy, prep.seg_ax, prep.seg_ay, prep.seg_ex, prep.seg_ey)
                )
            if prep.circles:
                centres = self._circle_centres(poses, prep.circles)
                hits.append(
                    circle_hits(
                        ox,
                        oy,
                        dx,
                        dy,
                        centres[:, 0:1],
                        centres[:, 1:2],
                        prep.circle_radii_sq,
                        prep.visible,
                    )
                )
            if not prep.every_robot:
                # the robots that cast no ray see nothing this step; the cast below
                # overwrites only the rows of those that do
                distance[:] = self.range
                raw[:] = self.baseline_raw
            if hits:
                # K objects × R rays: the nearest hit of each ray over the objects
                allt = hits[0] if len(hits) == 1 else np.concatenate(hits, axis=0)
                nearest = allt[0] if allt.shape[0] == 1 else allt.min(axis=0)
                dist = nearest.reshape(len(robots), 8, self.rays)
                # Hits beyond the cast length need no masking: the table keeps its last
                # value beyond TABLE_RANGE (as for ``inf``), and the distance is capped
                # at the range, which the cast length is at least.
                if prep.every_robot:
                    np.minimum(dist.min(axis=2), self.range, out=distance)
                    np.multiply(np.interp(dist, _D, _RAW), prep.weights).sum(axis=2, out=raw)
                else:
                    distance[prep.robots] = np.minimum(dist.min(axis=2), prep.range_col)
                    raw[prep.robots] = (np.interp(dist, _D, _RAW) * prep.weights).sum(axis=2)
            if z is not None:
                seen = distance < self.range
                # the table's own σ at the reported distance (the range if nothing is seen)
                sigma = np.hypot(noise, np.interp(distance, _D, _SIGMA))  # relative_sigma
                raw *= 1.0 + sigma * z
                # no test for "anything seen" first: on the two-robot pass something is
                # seen in 95 % of the steps that cast, and the masked copy handles neither
                noisy_distance = np.minimum(distance * (1.0 - 0.5 * noise * z), self.range)
                np.copyto(distance, noisy_distance, where=seen)
                np.maximum(distance, 0.0, out=distance)
        # two ufuncs: np.clip's Python wrapper costs more than the clamping itself
        np.maximum(raw, 0.0, out=raw)
        np.minimum(raw, RAW_MAX, out=raw)

    def _circle_centres(
        self, poses: Sequence[Sequence[float]], circles: tuple[int, ...]
    ) -> FloatArray:
        """C×2 centres of ``circles`` (static circles first, then robots at ``poses``)."""
        if not circles:
            return np.zeros((0, 2))
        n_static = self.n_static
        static = self.static_circles
        return np.array(
            [
                static[k][:2] if k < n_static else (poses[k - n_static][0], poses[k - n_static][1])
                for k in circles
            ]
        )

    def _far_sigma(self, noise: float) -> FloatArray:
        """N×8 relative noise σ of sensors that see nothing (they read the range)."""
        if noise != self._far_sigma_noise:
            at_range = np.broadcast_to(self.range, (self.n, 8))
            self._far_sigma_value = np.hypot(noise, relative_sigma(at_range))
            self._far_sigma_noise = noise
        return self._far_sigma_value
