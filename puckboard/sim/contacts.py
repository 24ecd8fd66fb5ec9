"""Contacts between round robots, static obstacles and arena walls.

Robots are pushed out of whatever they overlap along the contact normal (the line of
centres for circles, the nearest edge's normal or the direction to the nearest boundary
point for polygons, the wall normal for walls). Static things have infinite mass: only
the robot moves. Two robots share the correction equally. This is Enki's push-apart
without its impulse response: the e-puck's steppers hold the wheels, so a robot that
drives into something simply stops against it (and slides along it if it drives at an
angle), which is what a kinematic model should show.

The work per step is a handful of scalar tests, so it is done in plain Python floats:
for two robots and a few obstacles that costs a few microseconds, where each numpy call
would cost as much as the whole test. A bounding-circle check skips far objects. With
many robots a few numpy calls first find the robots near a static thing and the pairs
near each other (:mod:`.broadphase`), and only those are visited, in the same order.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from ..geometry import project_on_segment
from ..scenario.scene import Arena, CircleObstacle, PolygonObstacle
from .broadphase import close_pairs

__all__ = ["CONTACT_SLOP", "PLAIN_MAX", "Statics"]

FloatArray = npt.NDArray[np.float64]

#: Two bodies closer than the sum of their radii plus this (m) are in contact. Without a
#: slop, a robot pushed out to exactly touching distance would flicker in and out of
#: contact from one step to the next.
CONTACT_SLOP = 1e-4
#: Up to this many robots every robot and pair is visited in plain Python: cheaper than
#: the numpy calls that find the few that matter (measured on recorded positions: 19 µs
#: against 28 at 10 robots, 60 against 36 at 20, 299 against 64 at 50).
PLAIN_MAX = 12
#: Extra distance (m) within which robot pairs are visited: a pass whose pushes move a
#: robot by half of it or more is redone visiting every pair, so nothing is missed.
PAIR_MARGIN = 0.005
#: Extra distance (m) within which a robot's static tests run: far beyond rounding.
STATIC_MARGIN = 1e-4


class _Polygon:
    """A convex polygon as float tuples: vertices, outward unit normals, bounding circle."""

    __slots__ = ("cx", "cy", "edges", "radius")

    def __init__(self, vertices: np.ndarray) -> None:
        v = np.asarray(vertices, dtype=float)
        area2 = float(np.sum(v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1]))
        if area2 < 0:  # clockwise: make it counter-clockwise so normals point outwards
            v = v[::-1]
        centre = v.mean(axis=0)
        self.cx, self.cy = float(centre[0]), float(centre[1])
        self.radius = float(np.max(np.hypot(v[:, 0] - centre[0], v[:, 1] - centre[1])))
        edges = []
        for k in range(len(v)):
            ax, ay = float(v[k, 0]), float(v[k, 1])
            bx, by = float(v[(k + 1) % len(v), 0]), float(v[(k + 1) % len(v), 1])
            ex, ey = bx - ax, by - ay
            length = math.hypot(ex, ey)
            if length == 0.0:
                continue
            # outward normal of a counter-clockwise polygon: the edge turned clockwise
            edges.append((ax, ay, ex, ey, ey / length, -ex / length, length * length))
        self.edges = tuple(edges)

    def push(self, px: float, py: float, r: float) -> tuple[float, float] | None:
        """Correction moving a circle (px, py, r) out of the polygon, or None if apart."""
        best_s = -math.inf
        best_n = (0.0, 0.0)
        closest_d2 = math.inf
        closest = (0.0, 0.0)
        for ax, ay, ex, ey, nx, ny, len2 in self.edges:
            wx, wy = px - ax, py - ay
            s = wx * nx + wy * ny
            if s > best_s:
                best_s, best_n = s, (nx, ny)
            _, qx, qy = project_on_segment(wx, wy, ex, ey, len2)
            d2 = qx * qx + qy * qy
            if d2 < closest_d2:
                closest_d2, closest = d2, (qx, qy)
        if best_s <= 0.0:  # centre inside (or on) the polygon: leave by the nearest edge
            depth = r - best_s
            return best_n[0] * depth, best_n[1] * depth
        if closest_d2 >= (r + CONTACT_SLOP) ** 2:
            return None
        d = math.sqrt(closest_d2)
        depth = max(r - d, 0.0)
        return closest[0] / d * depth, closest[1] / d * depth


class Statics:
    """The static world a robot can bump into, prepared once per scene."""

    def __init__(
        self,
        obstacles: Sequence[CircleObstacle | PolygonObstacle],
        arena: Arena | None,
    ) -> None:
        self.circles = tuple(
            (float(o.x), float(o.y), float(o.radius))
            for o in obstacles
            if isinstance(o, CircleObstacle)
        )
        self.polygons = tuple(
            _Polygon(o.vertices) for o in obstacles if isinstance(o, PolygonObstacle)
        )
        self.arena = (
            None
            if arena is None
            else (float(arena.xmin), float(arena.ymin), float(arena.xmax), float(arena.ymax))
        )
        # the obstacles' names, in the order of circles then polygons, for messages only
        numbered = list(enumerate(obstacles, 1))
        order: list[tuple[int, CircleObstacle | PolygonObstacle]]
        order = [(k, o) for k, o in numbered if isinstance(o, CircleObstacle)]
        order += [(k, o) for k, o in numbered if not isinstance(o, CircleObstacle)]
        self._names = tuple(f"obstacle {o.name!r}" if o.name else f"obstacle {k}" for k, o in order)
        self._near_static_cache: tuple[tuple[float, ...], Any] | None = None

    def overlapping(self, x: float, y: float, r: float) -> list[str]:
        """What a robot of radius ``r`` at (``x``, ``y``) overlaps, in words ("obstacle
        'wedge'", "the arena's wall"): the start-pose warning names it, because a robot
        that is moved out of something at the start must say what it was moved out of."""
        found = [
            name
            for (cx, cy, cr), name in zip(self.circles, self._names)
            if math.hypot(x - cx, y - cy) < r + cr
        ]
        for poly, name in zip(self.polygons, self._names[len(self.circles) :]):
            corr = poly.push(x, y, r)
            if corr is not None and (corr[0] != 0.0 or corr[1] != 0.0):
                found.append(name)
        if self.arena is not None:
            xmin, ymin, xmax, ymax = self.arena
            if x < xmin + r or x > xmax - r or y < ymin + r or y > ymax - r:
                found.append("the arena's wall")
        return found

    def resolve(self, pos: list[list[float]], radii: Sequence[float]) -> list[bool]:
        """Push robots at ``pos`` (N [x, y] lists, modified in place) out of everything.

        Returns, per robot, whether it touched anything. A few passes settle chains
        (a robot pushed off a wall into another robot). Each pass pushes every robot out
        of the static things, in index order, then every touching pair apart, in (i, j)
        order; each correction sees the ones before it.

        For more than :data:`PLAIN_MAX` robots a pass only visits the robots near a static
        thing and the pairs near each other, found with a few numpy calls
        (:func:`~.broadphase.close_pairs`): the visits and their order are those of the
        plain loops minus visits that would do nothing, so the result is the same, and the
        cost per robot stays flat instead of growing with the number of pairs.
        """
        n = len(pos)
        if n <= PLAIN_MAX:
            return self._resolve_plain(pos, radii)
        return self._resolve_broad(pos, radii)

    def _resolve_plain(self, pos: list[list[float]], radii: Sequence[float]) -> list[bool]:
        """:meth:`resolve` by visiting every robot and every pair: the reference."""
        n = len(pos)
        contact = [False] * n
        every_pair = [(i, j) for i in range(n) for j in range(i + 1, n)]
        for _ in range(4):
            moved = False
            for i in range(n):
                moved = self._push_out(pos[i], radii[i], contact, i) or moved
            moved = _push_apart(pos, radii, contact, every_pair) or moved
            if not moved:
                break
        return contact

    def _resolve_broad(self, pos: list[list[float]], radii: Sequence[float]) -> list[bool]:
        """:meth:`resolve` visiting only the robots and pairs close enough to touch."""
        n = len(pos)
        contact = [False] * n
        near_static = self._near_static_test(radii)
        radius = np.asarray(radii, dtype=float)
        pair_reach = 2.0 * float(radius.max()) + CONTACT_SLOP + PAIR_MARGIN
        # the robots' positions as arrays, kept up to date as robots are pushed
        xy = np.array([(p[0], p[1]) for p in pos])
        for _ in range(4):
            moved = False
            # robots with a static thing within touching distance (and a margin), in
            # index order: the others' visit would test and change nothing
            for i in np.flatnonzero(near_static(xy[:, 0], xy[:, 1])).tolist():
                p = pos[i]
                if self._push_out(p, radii[i], contact, i):
                    moved = True
                    xy[i] = p[0], p[1]
            i_index, j_index = close_pairs(xy[:, 0], xy[:, 1], pair_reach)
            if i_index.shape[0]:
                pairs = list(zip(i_index.tolist(), j_index.tolist()))
                start = [(p[0], p[1]) for p in pos]
                before = list(contact)
                shift = _push_apart(pos, radii, contact, pairs, track=True)
                if shift is not None and 2.0 * max(shift) >= PAIR_MARGIN:
                    # a chain of pushes moved a robot far enough that a pair left out may
                    # have come into contact: redo this pass's pairs the plain way
                    for p, (x, y) in zip(pos, start):
                        p[0], p[1] = x, y
                    contact[:] = before
                    every_pair = [(i, j) for i in range(n) for j in range(i + 1, n)]
                    shift = _push_apart(pos, radii, contact, every_pair, track=True)
                if shift is not None:
                    moved = True
                    for i, step in enumerate(shift):
                        if step:
                            xy[i] = pos[i][0], pos[i][1]
            if not moved:
                break
        return contact

    def _near_static_test(self, radii: Sequence[float]) -> Any:
        """A function of the robots' x and y arrays: which robots may touch a static thing.

        Conservative by :data:`STATIC_MARGIN` beyond the plain test's distances, so
        rounding can never leave out a robot the plain loop would push. Built once per
        set of radii.
        """
        key = tuple(radii)
        cached = self._near_static_cache
        if cached is not None and cached[0] == key:
            return cached[1]
        r = np.asarray(radii, dtype=float)[:, None]
        grow = CONTACT_SLOP + STATIC_MARGIN
        centres = [(cx, cy, cr) for cx, cy, cr in self.circles]
        centres += [(poly.cx, poly.cy, poly.radius) for poly in self.polygons]
        cx = np.array([c[0] for c in centres])
        cy = np.array([c[1] for c in centres])
        limit = (r + np.array([c[2] for c in centres]) + grow) ** 2  # N×K
        arena = self.arena

        def near(x: FloatArray, y: FloatArray) -> npt.NDArray[np.bool_]:
            hit = np.zeros(x.shape[0], dtype=bool)
            if cx.shape[0]:
                dx = x[:, None] - cx
                dy = y[:, None] - cy
                hit |= np.any(dx * dx + dy * dy < limit, axis=1)
            if arena is not None:
                xmin, ymin, xmax, ymax = arena
                inner = r[:, 0] + grow
                hit |= (x < xmin + inner) | (x > xmax - inner)
                hit |= (y < ymin + inner) | (y > ymax - inner)
            return hit

        self._near_static_cache = (key, near)
        return near

    def _push_out(self, p: list[float], r: float, contact: list[bool], i: int) -> bool:
        """Push robot ``i`` (``p``, radius ``r``) out of every static thing; True if moved."""
        slop = CONTACT_SLOP
        moved = False
        for cx, cy, cr in self.circles:
            dx, dy = p[0] - cx, p[1] - cy
            reach = r + cr
            d2 = dx * dx + dy * dy
            if d2 < (reach + slop) ** 2:
                contact[i] = True
                if d2 < reach * reach:
                    d = math.sqrt(d2)
                    if d == 0.0:
                        dx, dy, d = 1.0, 0.0, 1.0
                    k = (reach - d) / d
                    p[0] += dx * k
                    p[1] += dy * k
                    moved = True
        for poly in self.polygons:
            dx, dy = p[0] - poly.cx, p[1] - poly.cy
            reach = r + poly.radius + slop
            if dx * dx + dy * dy >= reach * reach:
                continue
            corr = poly.push(p[0], p[1], r)
            if corr is not None:
                contact[i] = True
                if corr[0] != 0.0 or corr[1] != 0.0:
                    p[0] += corr[0]
                    p[1] += corr[1]
                    moved = True
        if self.arena is not None:
            xmin, ymin, xmax, ymax = self.arena
            for axis, lo, hi in ((0, xmin, xmax), (1, ymin, ymax)):
                if p[axis] < lo + r + slop:
                    contact[i] = True
                    if p[axis] < lo + r:
                        p[axis] = lo + r
                        moved = True
                if p[axis] > hi - r - slop:
                    contact[i] = True
                    if p[axis] > hi - r:
                        p[axis] = hi - r
                        moved = True
        return moved


def _push_apart(
    pos: list[list[float]],
    radii: Sequence[float],
    contact: list[bool],
    pairs: Iterable[tuple[int, int]],
    *,
    track: bool = False,
) -> Any:
    """Push every touching pair of ``pairs`` (i < j, in order) apart, sharing the correction.

    Returns whether anything moved; with ``track``, None if nothing moved, else each
    robot's total displacement (an upper bound: the sum of its corrections' lengths).
    """
    slop = CONTACT_SLOP
    moved = False
    shift: list[float] | None = None
    for i, j in pairs:
        pi = pos[i]
        pj = pos[j]
        dx, dy = pj[0] - pi[0], pj[1] - pi[1]
        reach = radii[i] + radii[j]
        d2 = dx * dx + dy * dy
        if d2 < (reach + slop) ** 2:
            contact[i] = contact[j] = True
            if d2 < reach * reach:
                d = math.sqrt(d2)
                if d == 0.0:
                    dx, dy, d = 1.0, 0.0, 1.0
                k = 0.5 * (reach - d) / d
                pi[0] -= dx * k
                pi[1] -= dy * k
                pj[0] += dx * k
                pj[1] += dy * k
                moved = True
                if track:
                    if shift is None:
                        shift = [0.0] * len(pos)
                    step = abs(dx * k) + abs(dy * k)
                    shift[i] += step
                    shift[j] += step
    return shift if track else moved
