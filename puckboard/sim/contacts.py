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
would cost as much as the whole test. A bounding-circle check skips far objects.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ..scenario.scene import Arena, CircleObstacle, PolygonObstacle

__all__ = ["CONTACT_SLOP", "Statics"]

#: Two bodies closer than the sum of their radii plus this (m) are in contact. Without a
#: slop, a robot pushed out to exactly touching distance would flicker in and out of
#: contact from one step to the next.
CONTACT_SLOP = 1e-4


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
            t = (wx * ex + wy * ey) / len2
            t = 0.0 if t < 0.0 else 1.0 if t > 1.0 else t
            qx, qy = wx - t * ex, wy - t * ey
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

    def resolve(self, pos: list[list[float]], radii: Sequence[float]) -> list[bool]:
        """Push robots at ``pos`` (N [x, y] lists, modified in place) out of everything.

        Returns, per robot, whether it touched anything. A few passes settle chains
        (a robot pushed off a wall into another robot).
        """
        n = len(pos)
        contact = [False] * n
        slop = CONTACT_SLOP
        for _ in range(4):
            moved = False
            for i in range(n):
                p = pos[i]
                r = radii[i]
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
            for i in range(n):
                pi = pos[i]
                for j in range(i + 1, n):
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
            if not moved:
                break
        return contact
