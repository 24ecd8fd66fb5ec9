"""V-REP's proximity sensor in 2-D: the exact distance to the nearest point inside a cone.

V-REP's (and CoppeliaSim's) e-puck model senses with cone-shaped proximity sensors: each
reports the exact distance from its origin to the nearest point of any object inside its
volume, a 30° cone detecting from 1.5 mm to 41.5 mm, with no noise and no angle of
incidence check (the V-REP e-puck model reference, "Proximity sensor semantics"). The
robots of the embedded world live in a plane, so the cone becomes a sector:

* a **circle** (a round obstacle, another robot's body) is seen at its nearest point when
  the direction to its centre lies inside the sector, else at the first point where one
  of the sector's two edges enters it (the nearest point of a convex set inside a convex
  sector lies on the sector's boundary when the unconstrained nearest point is outside);
* a **segment** (a polygon's edge, a wall) is seen at the nearest of: its point nearest
  to the sensor, its two ends, and where the sector's edges cross it, among those that lie
  inside the sector.

A sensor then reads the smallest of those distances if it lies between the profile's
``prox_min_distance`` and ``prox_max_distance``, and "nothing" (the profile's
``prox_range``) otherwise: an object nearer than 1.5 mm blinds the sensor, as in V-REP.
Everything is computed for all sensors of all cone robots and all objects at once, as
M×K arrays (M sensors, K objects), a handful of numpy calls per step.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from ..ir_response import raw_from_distance
from ..profile import RobotProfile

__all__ = ["ConeSensors"]

FloatArray = npt.NDArray[np.float64]

#: Slack (rad) on the sector's half-angle, so a point exactly on an edge counts as inside.
_EDGE_SLACK = 1e-9


class ConeSensors:
    """The cone-model proximity sensors of the robots ``robots`` (indices into the world).

    ``static_circles`` are (x, y, r) of round obstacles; every robot's body is a circle of
    its profile's ``body_radius`` at its pose; ``seg_start``/``seg_vector`` (K×2) are
    every static segment. A robot never sees its own body.
    """

    def __init__(
        self,
        profiles: Sequence[RobotProfile],
        robots: Sequence[int],
        *,
        static_circles: Sequence[tuple[float, float, float]],
        seg_start: FloatArray,
        seg_vector: FloatArray,
    ) -> None:
        self.robots = np.array(robots, dtype=np.intp)
        #: world robot index -> position among the cone robots
        self._cone_index = {int(i): c for c, i in enumerate(robots)}
        every = list(robots) == list(range(len(profiles)))
        self._rows: slice | npt.NDArray[np.intp] = slice(None) if every else self.robots
        cone = [profiles[i] for i in robots]
        self.n_robots = len(profiles)
        self.local_x = np.array([[q.x for q in p.prox_poses] for p in cone]).reshape(-1, 8)
        self.local_y = np.array([[q.y for q in p.prox_poses] for p in cone]).reshape(-1, 8)
        self.local_heading = np.array([[q.heading for q in p.prox_poses] for p in cone]).reshape(
            -1, 8
        )
        half = np.array([p.prox_aperture / 2.0 for p in cone])
        self.half = np.repeat(half, 8)  # one per sensor, flattened like the apexes
        self.cos_half = np.cos(self.half + _EDGE_SLACK)
        self.min_distance = np.repeat([p.prox_min_distance for p in cone], 8)
        self.max_distance = np.repeat([p.prox_max_distance for p in cone], 8)
        self.nothing = np.array([p.prox_range for p in cone])[:, None]  # C×1
        self.nothing_raw = float(raw_from_distance(np.inf))
        self.static = np.array(static_circles, dtype=float).reshape(-1, 3)
        self.body_radii = np.array([p.body_radius for p in profiles])
        self.seg_a = np.asarray(seg_start, dtype=float).reshape(-1, 2)
        self.seg_e = np.asarray(seg_vector, dtype=float).reshape(-1, 2)
        # which circle each sensor may see: static ones, and every robot but its own
        k_static = len(self.static)
        own = np.zeros((len(robots) * 8, k_static + self.n_robots), dtype=bool)
        for c, i in enumerate(robots):
            own[c * 8 : (c + 1) * 8, k_static + i] = True
        self.own_body = own

    # -- the step ------------------------------------------------------------------------------
    def sense(
        self,
        poses: Sequence[Sequence[float]],
        distance: FloatArray,
        raw: FloatArray,
        near: Sequence[int] | None = None,
    ) -> None:
        """Write the cone robots' rows of ``distance`` (N×8 m) and ``raw`` for ``poses``.

        ``near`` (world robot indices) says which cone robots have anything within reach,
        from the ray sensors' conservative broad phase; the others read nothing without a
        single geometric test, which is most steps of a line-following run.
        """
        if not len(self.robots):
            return
        rows = self._rows  # a slice when every robot is a cone robot: cheaper to assign
        distance[rows] = self.nothing
        raw[rows] = self.nothing_raw
        if near is None:
            active = np.arange(len(self.robots))
        else:
            if not near:
                return  # nothing within any cone robot's reach (most steps)
            cone_index = self._cone_index
            picked = [cone_index[i] for i in near if i in cone_index]
            if not picked:
                return
            active = np.array(picked, dtype=np.intp)
        rows = self.robots
        p = np.asarray(poses, dtype=float)
        own = p[rows[active]]
        lx, ly, lh = self.local_x[active], self.local_y[active], self.local_heading[active]
        sensors = (active[:, None] * 8 + np.arange(8)).reshape(-1)
        c, s = np.cos(own[:, 2:3]), np.sin(own[:, 2:3])
        apex_x = (own[:, 0:1] + c * lx - s * ly).reshape(-1)
        apex_y = (own[:, 1:2] + s * lx + c * ly).reshape(-1)
        heading = (own[:, 2:3] + lh).reshape(-1)
        nearest = np.minimum(
            self._circles(p, apex_x, apex_y, heading, sensors),
            self._segments(apex_x, apex_y, heading, sensors),
        )
        low, high = self.min_distance[sensors], self.max_distance[sensors]
        reading = np.where((nearest >= low) & (nearest <= high), nearest, np.inf).reshape(-1, 8)
        seen = np.isfinite(reading)
        chosen = rows[active]
        distance[chosen] = np.where(seen, reading, self.nothing[active])
        raw[chosen] = np.where(seen, raw_from_distance(reading), self.nothing_raw)

    def _circles(
        self,
        poses: FloatArray,
        apex_x: FloatArray,
        apex_y: FloatArray,
        heading: FloatArray,
        sensors: npt.NDArray[np.intp],
    ) -> FloatArray:
        """M nearest in-sector distances to any circle (inf where none is inside)."""
        centres = np.concatenate([self.static[:, :2], poses[:, :2]])
        radii = np.concatenate([self.static[:, 2], self.body_radii])
        vx = centres[None, :, 0] - apex_x[:, None]  # M×K
        vy = centres[None, :, 1] - apex_y[:, None]
        dist = np.hypot(vx, vy)
        ux, uy = np.cos(heading)[:, None], np.sin(heading)[:, None]
        # the circle's nearest point lies along the direction to its centre
        half = self.half[sensors]
        towards = vx * ux + vy * uy >= dist * self.cos_half[sensors][:, None]
        best = np.where(towards, np.maximum(dist - radii, 0.0), np.inf)
        best = np.where(dist <= radii, 0.0, best)  # the sensor inside the circle
        # both edges of the sector at once (axis 1): where each first enters the circle
        edges = heading[:, None] + np.stack([-half, half], axis=1)  # M×2
        bx, by = np.cos(edges)[:, :, None], np.sin(edges)[:, :, None]
        along = vx[:, None, :] * bx + vy[:, None, :] * by  # M×2×K
        disc = radii * radii - ((dist * dist)[:, None, :] - along * along)
        root = np.sqrt(np.maximum(disc, 0.0))
        enters = (disc >= 0.0) & (along + root >= 0.0)
        on_edges = np.where(enters, np.maximum(along - root, 0.0), np.inf).min(axis=1)
        best = np.minimum(best, on_edges)
        best[self.own_body[sensors]] = np.inf
        return best.min(axis=1) if best.shape[1] else np.full(len(apex_x), np.inf)

    def _segments(
        self,
        apex_x: FloatArray,
        apex_y: FloatArray,
        heading: FloatArray,
        sensors: npt.NDArray[np.intp],
    ) -> FloatArray:
        """M nearest in-sector distances to any segment (inf where none is inside)."""
        if not len(self.seg_a):
            return np.full(len(apex_x), np.inf)
        ax = self.seg_a[None, :, 0] - apex_x[:, None]  # segment start relative to the apex
        ay = self.seg_a[None, :, 1] - apex_y[:, None]
        ex, ey = self.seg_e[None, :, 0], self.seg_e[None, :, 1]
        ux, uy = np.cos(heading)[:, None], np.sin(heading)[:, None]
        cos_half = self.cos_half[sensors][:, None]
        half = self.half[sensors]

        def inside(px: FloatArray, py: FloatArray) -> FloatArray:
            d = np.hypot(px, py)
            ok = (px * ux + py * uy >= d * cos_half) | (d == 0.0)
            return np.where(ok, d, np.inf)

        length2 = ex * ex + ey * ey
        t = np.clip(-(ax * ex + ay * ey) / np.where(length2 > 0, length2, 1.0), 0.0, 1.0)
        best = inside(ax + t * ex, ay + t * ey)
        best = np.minimum(best, inside(ax, ay))
        best = np.minimum(best, inside(ax + ex, ay + ey))
        for side in (-1.0, 1.0):
            edge = heading + side * half
            bx, by = np.cos(edge)[:, None], np.sin(edge)[:, None]
            # apex + r·b = a + s·e: solve for r ≥ 0 and 0 ≤ s ≤ 1
            denom = bx * ey - by * ex
            safe = np.where(np.abs(denom) > 1e-15, denom, np.nan)  # parallel: never crosses
            r = (ax * ey - ay * ex) / safe
            s_on = (ax * by - ay * bx) / safe
            crosses = (r >= 0.0) & (s_on >= 0.0) & (s_on <= 1.0)
            best = np.minimum(best, np.where(crosses, r, np.inf))
        return best.min(axis=1)
