"""Where a point is along a track: the nearest point of the line, as an arc length.

The judge asks this every control cycle for every robot, twice (its centre, to follow
its progress while it is within ``near_line`` of the line, and the point between its
ground sensors, to tell whether it is on the line). Two ways, the same answer to the
last bit:

* :meth:`TrackProjector.project` tests P points against every segment at once in
  numpy (the judge's start, an obstacle's place on the line);
* a :class:`NearestSegment` follows one point from cycle to cycle and tests only the
  segments that can be nearest, in plain floats. When it last measured every segment
  (from ``p0``), segment ``j`` was ``D_j`` away; a point that has since moved ``m`` is
  at least ``D_j - m`` from it (the triangle inequality). So it tests segments in order
  of ``D_j`` and stops at the first whose bound exceeds the nearest distance found (or
  the radius asked about): every segment left untested is then strictly farther, and
  the one found is the one the full test finds, ties going to the lower index as
  numpy's ``argmin`` gives them. A point far from the line tests nothing until it comes
  within reach; once the bounds have loosened so much that many segments must be
  tested, it measures every segment again from where it is.

Each segment is tested with :func:`~puckboard.geometry.project_on_segments`'s arithmetic
in the same order (multiplying by the reciprocal of the squared length), so the plain
floats give the same values as the arrays (IEEE operations, one at a time, round alike);
``tests/scenario/test_track_position.py`` compares the two on random tracks and points.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from ..geometry import project_on_segments

__all__ = ["NearestSegment", "TrackProjector"]

FloatArray = npt.NDArray[np.float64]

#: Slack (m) on every bound: far above the rounding of a few operations on metres, far
#: below anything a judge threshold tells apart.
BOUND_SLACK = 1e-9
#: Segments a query may test before its point measures every segment again.
RETEST_AFTER = 6


class TrackProjector:
    """Nearest point on a polyline, as arc length, for several points at once.

    One P×S array per quantity (P points, S segments); per-segment data are kept as
    contiguous 1-D arrays so each numpy call streams through memory once.
    """

    def __init__(self, segments: FloatArray, closed: bool) -> None:
        d = segments[:, 1] - segments[:, 0]
        self.ax = np.ascontiguousarray(segments[:, 0, 0])
        self.ay = np.ascontiguousarray(segments[:, 0, 1])
        self.dx = np.ascontiguousarray(d[:, 0])
        self.dy = np.ascontiguousarray(d[:, 1])
        self.seg_len = np.hypot(self.dx, self.dy)
        self.inv_len2 = 1.0 / np.maximum(self.seg_len**2, 1e-18)
        self.heading = np.arctan2(self.dy, self.dx)
        self.cum = np.concatenate([[0.0], np.cumsum(self.seg_len)])[:-1]
        self.length = float(self.seg_len.sum())
        self.closed = closed
        #: per segment (ax, ay, dx, dy, 1/|d|²) as plain floats, for :class:`NearestSegment`
        self.segments: list[tuple[float, float, float, float, float]] = list(
            zip(
                self.ax.tolist(), self.ay.tolist(), self.dx.tolist(), self.dy.tolist(),
                self.inv_len2.tolist(),
            )
        )  # fmt: skip
        #: per segment (arc length at its start, its length), as plain floats
        self.arcs: list[tuple[float, float]] = list(zip(self.cum.tolist(), self.seg_len.tolist()))

    def _squared(self, points: FloatArray) -> tuple[FloatArray, FloatArray]:
        """(t, squared distance) of P×2 points against every segment (P×S each)."""
        t, wx, wy = project_on_segments(
            points[:, 0:1] - self.ax, points[:, 1:2] - self.ay, self.dx, self.dy,
            inv_len2=self.inv_len2,
        )  # fmt: skip
        wx *= wx
        wy *= wy
        wx += wy  # squared distance
        return t, wx

    def project(self, points: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(arc position, distance to the line, track heading there) for P×2 points."""
        t, d2 = self._squared(points)
        best = np.argmin(d2, axis=1)
        rows = np.arange(len(points))
        arc = self.cum[best] + t[rows, best] * self.seg_len[best]
        return arc, np.sqrt(d2[rows, best]), self.heading[best]

    def distances(self, x: float, y: float) -> FloatArray:
        """The distance from (x, y) to every segment."""
        _, d2 = self._squared(np.array([[x, y]]))
        return np.sqrt(d2[0])


class NearestSegment:
    """One point followed along ``track`` from cycle to cycle; see the module docstring."""

    def __init__(self, track: TrackProjector) -> None:
        self.track = track
        self._x0 = self._y0 = math.nan  # where every segment was last measured from
        self._order: list[int] = []  # segments, nearest to (x0, y0) first
        self._bound: list[float] = []  # their distances from there, less the slack
        self._retest = True

    def query(self, x: float, y: float, radius: float) -> tuple[int, float, float] | None:
        """``(segment, t, squared distance)`` of the segment nearest (x, y) when it lies
        within ``radius`` (``t`` in [0, 1] locates the nearest point on it), else None:
        what :meth:`TrackProjector.project` finds, to the bit."""
        if self._retest:
            self._measure(x, y)
        moved = math.hypot(x - self._x0, y - self._y0)
        segments = self.track.segments
        best = -1
        best_t = best_d2 = math.inf
        # squared distances, to save a square root per segment: the bound's slack is
        # far larger than what squaring rounds
        reach2 = radius * radius  # no segment beyond reach matters
        bound = self._bound
        tested = 0
        for j in self._order:
            lower = bound[tested] - moved
            if lower > 0.0 and lower * lower > reach2:
                break  # this one and every one after it lie beyond reach
            ax, ay, ex, ey, inv = segments[j]
            wx = x - ax
            wy = y - ay
            t = wx * ex
            t += wy * ey
            t *= inv
            if t < 0.0:
                t = 0.0
            elif t > 1.0:
                t = 1.0
            qx = wx - t * ex
            qy = wy - t * ey
            d2 = qx * qx + qy * qy
            tested += 1
            if d2 < best_d2 or (d2 == best_d2 and j < best):
                best, best_t, best_d2 = j, t, d2
                if d2 < reach2:
                    reach2 = d2
        self._retest = tested > RETEST_AFTER
        if best < 0 or math.sqrt(best_d2) > radius:
            return None
        return best, best_t, best_d2

    def _measure(self, x: float, y: float) -> None:
        """Measure every segment from (x, y) and order them, nearest first."""
        distances = self.track.distances(x, y)
        order = np.argsort(distances, kind="stable")
        self._order = order.tolist()
        self._bound = (distances[order] - BOUND_SLACK).tolist()
        self._x0, self._y0 = x, y
        self._retest = False
