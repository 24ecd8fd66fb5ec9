"""Broad phases: which robots are close to each other, and what each robot's sensors may see.

The IR sensors and the contacts need, every step, the pairs of robots close enough to
matter (within a sensor's reach, or touching). Testing every pair costs N²/2 distance
tests: in plain Python that is what made the cost per robot-step grow with the number of
robots (1,225 pairs at 50 robots, ≈200 µs per step for the IR broad phase alone).

Sweep and prune sorts the robots along x once and pairs each robot only with those
whose x lies within ``reach`` of its own (one ``searchsorted``), then keeps the
candidates that are really within ``reach``. It is a dozen numpy calls whatever the
number of robots: measured on this project's 2-core VM, 16–17 µs from 10 to 50 robots
and 30 µs at 200, where a dense N×N distance matrix costs 7 µs at 10, 16 µs at 50 and
540 µs at 200. A uniform grid gives the same pairs, but finding each robot's neighbour
cells is a Python loop or many more numpy calls; along one axis the sort does it.
SciPy's ``cKDTree`` (build, then ``query_pairs``) was measured beside it on the same VM
under load: slower up to about 30 points (17–40 µs against 8–21 µs at 10), faster from
50 (62–65 against 87–94 µs; 186 against 286–327 µs at 200). At 50 robots, though, the
pairs are about 1 % of a step (world steps of the swarm arena, three interleaved A/B
runs of 300 steps: 3,039 µs CPU median with this module, 3,352 µs with the tree, the
same results to the bit), and the two-robot scenes never call it: not worth making
SciPy, today only a dependency of filterpy, one of the engine's.

The pairs returned are a *superset* of those within ``reach`` (the sweep's window is
widened by a hair so floating-point rounding can never drop a pair): callers apply their
own exact test to each pair, with their own arithmetic, so what they decide does not
depend on this module. ``tests/sim/test_sim_broadphase.py`` checks the superset against
brute force on random scenes.

:class:`SensorBroadPhase` builds on it for the proximity sensors: which circles and
segments each robot may see within its sensors' reach. Both sensor models, the IR rays
(:mod:`.proximity`) and V-REP's cones (:mod:`.cone`), ask it, each with its own robots
and reach; neither knows of the other.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from ..geometry import project_on_segment, project_on_segments

__all__ = [
    "DENSE_MAX",
    "PYTHON_BROAD_PHASE_MAX",
    "PolygonBound",
    "SensorBroadPhase",
    "WallSegment",
    "close_pairs",
]

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.intp]
BoolArray = npt.NDArray[np.bool_]

#: Up to this many points every pair is measured (an N×N array: 7 µs at 10 points, 16 µs
#: at 50); above, the sweep (17 µs at 50, 30 µs at 200, where the N×N array costs 540 µs).
DENSE_MAX = 48
#: Relative and absolute widening (m) of the sweep's window and final test: the pairs
#: are a superset of the exact ones whatever the rounding of the sums below.
_WIDEN_REL = 1e-9
_WIDEN_ABS = 1e-12


def close_pairs(x: FloatArray, y: FloatArray, reach: float) -> tuple[IntArray, IntArray]:
    """Index pairs ``(i, j)``, ``i < j``, of points closer than ``reach`` (m), and maybe
    a few more at that distance to within rounding; sorted by ``i``, then ``j``.

    ``x`` and ``y`` are the points' coordinates (length N each).
    """
    n = x.shape[0]
    if n < 2:
        empty = np.zeros(0, dtype=np.intp)
        return empty, empty
    wide = reach * (1.0 + _WIDEN_REL) + _WIDEN_ABS
    if n <= DENSE_MAX:
        # every pair at once: fewer numpy calls than the sweep while N² is small
        dx = x[:, None] - x
        dy = y[:, None] - y
        i, j = np.nonzero(dx * dx + dy * dy < wide * wide)
        upper = i < j
        return i[upper], j[upper]
    order = np.argsort(x, kind="stable")
    xs = x[order]
    # sorted position a pairs with the positions a+1 .. hi[a]-1 (x within the window)
    hi = np.searchsorted(xs, xs + wide, side="right")
    counts = hi - np.arange(1, n + 1)
    total = int(counts.sum())
    if total == 0:
        empty = np.zeros(0, dtype=np.intp)
        return empty, empty
    a = np.repeat(np.arange(n), counts)
    # the k-th candidate of position a is a + 1 + k
    first = np.cumsum(counts) - counts
    b = np.arange(total) - np.repeat(first, counts) + a + 1
    i, j = order[a], order[b]
    dx = x[i] - x[j]
    dy = y[i] - y[j]
    keep = dx * dx + dy * dy < wide * wide
    i, j = i[keep], j[keep]
    lo = np.minimum(i, j)
    hi_index = np.maximum(i, j)
    by_pair = np.argsort(lo * n + hi_index, kind="stable")
    return lo[by_pair], hi_index[by_pair]


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


#: Up to this many robots :class:`SensorBroadPhase` answers in plain Python (and the ray
#: sensors cache each outcome's arrays); above, in numpy. Its ≈60 calls cost more than the
#: loops for a few robots and less from about 30 (phase and cast, measured: Python 30, 62,
#: 229, 415 µs at 3, 10, 30, 50 robots; numpy 79, 111, 218, 294 µs). Read at every call.
PYTHON_BROAD_PHASE_MAX = 24

Candidates = dict[int, tuple[tuple[int, ...], tuple[int, ...]]]


class SensorBroadPhase:
    """Which objects each robot of one sensor model may see within its reach.

    Both proximity models, the IR rays (:mod:`.proximity`) and V-REP's cones
    (:mod:`.cone`), test a robot's sensors only against what lies within their reach of
    its centre, and a robot with nothing there reads "nothing" without a geometric test
    (most steps of a line-following run). Each model has one of these for its own robots,
    ``seers`` (world indices), with its own ``reach`` (m, one per seer: the rays' is
    longer than the cones'); every robot of the world, of either model, is a circle of
    ``radii[j]`` that the seers may see.

    Conservative (bounding circles for polygons, exact distances to the walls), so it never
    drops an object the sensors could see. Circle indices count the static circles first,
    then the robots (``n_static + j``); segment indices are those of the scene's surfaces.
    It answers in plain Python (:meth:`lists`) or in numpy (:meth:`arrays`), with the same
    arithmetic per pair: ``tests/sim/test_sim_broadphase.py`` compares the two.
    """

    def __init__(
        self,
        seers: Sequence[int],
        reach: Sequence[float],
        radii: Sequence[float],
        *,
        static_circles: Sequence[tuple[float, float, float]],
        polygons: Sequence[PolygonBound],
        walls: Sequence[WallSegment],
        n_segments: int,
    ) -> None:
        n = len(radii)
        self.n = n
        by_seer = sorted(zip(seers, reach))
        self.seers = tuple(i for i, _ in by_seer)
        reach = [r for _, r in by_seer]
        self.n_static = n_static = len(static_circles)
        self._n_segments = n_segments
        walls_data = tuple(
            (w.ax, w.ay, w.ex, w.ey, w.ex * w.ex + w.ey * w.ey, w.index) for w in walls
        )
        self._walls_data = walls_data
        # squared limits, computed once per distinct reach (one for the rays)
        by_reach: dict[float, tuple[tuple[Any, ...], tuple[Any, ...]]] = {}
        for r in set(reach):
            by_reach[r] = (
                tuple(
                    (k, cx, cy, (r + cr) * (r + cr))
                    for k, (cx, cy, cr) in enumerate(static_circles)
                ),
                tuple((p.x, p.y, (r + p.radius) * (r + p.radius), p.segments) for p in polygons),
            )
        #: per seer: its index, its reach squared and its static circles' and polygons' limits
        self._seer_bounds = tuple(
            (i, r * r, by_reach[r][0], by_reach[r][1]) for i, r in zip(self.seers, reach)
        )
        # seer i may see robot j within (reach of i + radius of j); the others see nothing
        reach_of = [0.0] * n
        for i, r in zip(self.seers, reach):
            reach_of[i] = r
        seer = np.zeros(n, dtype=bool)
        seer[list(self.seers)] = True
        self._robot_lim2 = [
            [(reach_of[i] + rj) * (reach_of[i] + rj) if seer[i] else -1.0 for rj in radii]
            for i in range(n)
        ]
        # the same limits as arrays, for the numpy answer (the same floats)
        self._every = len(self.seers) == n
        self._seer = seer
        self._seer_array = np.array(self.seers, dtype=np.intp)
        self._seer_position = np.full(n, -1, dtype=np.intp)
        self._seer_position[self._seer_array] = np.arange(len(self.seers))
        self._reach_array = np.array(reach_of)
        self._radius_array = np.array(radii, dtype=float)
        self._pair_reach = (max(reach) if len(reach) else 0.0) + (max(radii) if n else 0.0)
        # static circles and polygons' bounding circles: centres (2×K), limits (seers×K)
        bounds = [(cx, cy, cr) for cx, cy, cr in static_circles]
        bounds += [(p.x, p.y, p.radius) for p in polygons]
        self._bounds = np.array(bounds, dtype=float).reshape(-1, 3)[:, :2].T.copy()
        self._bounds_limit = np.array(
            [
                [b[3] for b in circles] + [b[2] for b in polys]
                for _, _, circles, polys in self._seer_bounds
            ],
            dtype=float,
        ).reshape(len(self.seers), self._bounds.shape[1])
        self._wall_reach2 = np.array([b[1] for b in self._seer_bounds])[:, None]
        self._poly_segments = np.array([k for p in polygons for k in p.segments], dtype=np.intp)
        self._poly_owner = n_static + np.array(
            [owner for owner, p in enumerate(polygons) for _ in p.segments], dtype=np.intp
        )
        self._walls = np.array([w[:5] for w in walls_data], dtype=float).reshape(-1, 5).T.copy()
        self._wall_segments = np.array([w[5] for w in walls_data], dtype=np.intp)

    def in_python(self) -> bool:
        """Whether the world is small enough for the plain-Python answer (:meth:`lists`)."""
        return self.n <= PYTHON_BROAD_PHASE_MAX

    def candidates(self, poses: Sequence[Sequence[float]]) -> Candidates:
        """Per seer with anything within reach (in increasing order), the circles and
        segments it may see; whichever answer suits the world's size."""
        if self.in_python():
            near, circles_of, segments_of = self.lists(poses)
            return {i: (tuple(circles_of[i]), tuple(segments_of[i])) for i in near}
        near_array, rows, cols, seg_hit = self.arrays(np.array(poses)[:, :2])
        near = near_array.tolist()
        circles: list[list[int]] = [[] for _ in near]
        for r, c in zip(rows.tolist(), cols.tolist()):
            circles[r].append(c)
        return {
            i: (tuple(sorted(circles[r])), tuple(np.flatnonzero(seg_hit[r]).tolist()))
            for r, i in enumerate(near)
        }

    def lists(
        self, poses: Sequence[Sequence[float]]
    ) -> tuple[list[int], list[list[int]], list[list[int]]]:
        """The seers with anything within reach (increasing), and per robot (all N, empty
        for the others) the circles and segments it may see, in plain Python."""
        near: list[int] = []
        n = self.n
        n_static = self.n_static
        circles_of: list[list[int]] = [[] for _ in range(n)]
        segments_of: list[list[int]] = [[] for _ in range(n)]
        # each robot pair's distance once: i may see j, and j may see i
        lim2 = self._robot_lim2
        for i in range(n):
            xi, yi = poses[i][0], poses[i][1]
            for j in range(i + 1, n):
                dx, dy = xi - poses[j][0], yi - poses[j][1]
                d2 = dx * dx + dy * dy
                if d2 < lim2[i][j]:
                    circles_of[i].append(n_static + j)
                if d2 < lim2[j][i]:
                    circles_of[j].append(n_static + i)
        for i, reach2, circle_bounds, polygon_bounds in self._seer_bounds:
            x, y = poses[i][0], poses[i][1]
            circles = circles_of[i]
            segments = segments_of[i]
            for k, cx, cy, climit in circle_bounds:
                dx, dy = x - cx, y - cy
                if dx * dx + dy * dy < climit:
                    circles.append(k)
            for px, py, plimit, poly_segments in polygon_bounds:
                dx, dy = x - px, y - py
                if dx * dx + dy * dy < plimit:
                    segments.extend(poly_segments)
            for ax, ay, ex, ey, len2, k in self._walls_data:
                _, qx, qy = project_on_segment(x - ax, y - ay, ex, ey, len2)
                if qx * qx + qy * qy < reach2:
                    segments.append(k)
            if circles or segments:
                near.append(i)
        return near, circles_of, segments_of

    def arrays(self, xy: FloatArray) -> tuple[IntArray, IntArray, IntArray, BoolArray]:
        """The same answer as :meth:`lists` from robot positions ``xy`` (N×2), in numpy.

        Returns the seers with anything within reach (``near``, k of them, increasing), the
        (row, circle) candidate pairs (``row`` 0..k-1 is a position in ``near``) and which
        segments each of them may see (k×segments). Robot pairs come from
        :func:`close_pairs`, static objects from one seers×K test per kind.
        """
        n = self.n
        x = xy[:, 0]
        y = xy[:, 1]
        rows: list[IntArray] = []  # (robot, circle) candidates
        cols: list[IntArray] = []
        i, j = close_pairs(x, y, self._pair_reach)
        if i.shape[0]:
            dx = x[i] - x[j]
            dy = y[i] - y[j]
            d2 = dx * dx + dy * dy
            # (reach of the seer + radius of the seen)², as the Python answer
            reach, radius = self._reach_array, self._radius_array
            i_lim = reach[i] + radius[j]
            j_lim = reach[j] + radius[i]
            i_sees_j = d2 < i_lim * i_lim
            j_sees_i = d2 < j_lim * j_lim
            if not self._every:
                i_sees_j &= self._seer[i]
                j_sees_i &= self._seer[j]
            rows += [i[i_sees_j], j[j_sees_i]]
            cols += [j[i_sees_j] + self.n_static, i[j_sees_i] + self.n_static]
        # the seers' own rows from here on (every robot's when all are seers)
        seers = self._seer_array
        sx0, sy0 = (x, y) if self._every else (x[seers], y[seers])
        seg_hit = np.zeros((seers.shape[0], self._n_segments), dtype=bool)
        if self._bounds.shape[1]:
            bx, by = self._bounds
            sx = sx0[:, None] - bx
            sy = sy0[:, None] - by
            bound_hit = sx * sx + sy * sy < self._bounds_limit
            if self.n_static:
                r, c = np.nonzero(bound_hit[:, : self.n_static])
                rows.append(r if self._every else seers[r])
                cols.append(c)
            if self._poly_segments.shape[0]:
                seg_hit[:, self._poly_segments] = bound_hit[:, self._poly_owner]
        if self._wall_segments.shape[0]:
            ax, ay, ex, ey, len2 = self._walls
            _, qx, qy = project_on_segments(sx0[:, None] - ax, sy0[:, None] - ay, ex, ey, len2=len2)
            seg_hit[:, self._wall_segments] = qx * qx + qy * qy < self._wall_reach2
        circle_rows = np.concatenate(rows) if rows else np.zeros(0, dtype=np.intp)
        circle_cols = np.concatenate(cols) if cols else np.zeros(0, dtype=np.intp)
        if self._every:
            found: BoolArray = np.any(seg_hit, axis=1)
        else:
            found = np.zeros(n, dtype=bool)
            found[seers] = np.any(seg_hit, axis=1)
        found[circle_rows] = True
        near = np.flatnonzero(found)
        k = near.shape[0]
        if k < n:
            # each candidate row's position in near (every row's robot is near)
            column = np.full(n, -1, dtype=np.intp)
            column[near] = np.arange(k)
            circle_rows = column[circle_rows]
        if k < seers.shape[0]:
            seg_hit = seg_hit[self._seer_position[near]]
        return near, circle_rows, circle_cols, seg_hit
