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
Its raw value is what a real e-puck would send for that distance, the calibrated curve
(:func:`puckboard.ir_response.calibrated_from_distance`), 0 for nothing: V-REP reports
no such value, and a threshold on ``raw`` then means the same with every profile.
Everything is computed for all sensors of the cone robots at once, as M×K arrays (M
sensors, K objects), a handful of numpy calls per step. A cone sees nothing beyond its
maximum distance from its apex, so the cone robots have a broad phase of their own
(:class:`~.broadphase.SensorBroadPhase`, with that reach: a third less than the IR rays')
that first finds which robots have anything that near, and what: the others read
"nothing" without a geometric test (most steps), the rest test only their candidates.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from ..ir_response import calibrated_from_distance
from ..profile import RobotProfile
from .broadphase import PolygonBound, SensorBroadPhase, WallSegment

__all__ = ["ConeSensors"]

FloatArray = npt.NDArray[np.float64]

#: Slack (rad) on the sector's half-angle, so a point exactly on an edge counts as inside.
_EDGE_SLACK = 1e-9


#: Where the padding of a robot's candidate list sits: a circle of radius 0 and a
#: zero-length segment this far away (m) are always seen beyond any sensor's range.
_FAR = 1e9


@dataclass(frozen=True)
class _Plan:
    """What one set of active cone robots and their candidates needs, built once.

    ``M`` = 8 × active robots sensors; each sensor tests its robot's candidate circles
    (M×C indices into the circle table, padded with the far circle) and segments (M×S).
    Without candidates every circle is tested (1×K) and a robot's own body is masked.
    """

    chosen: npt.NDArray[np.intp]  # world indices of the active robots
    chosen_list: tuple[int, ...]
    local_x: FloatArray
    local_y: FloatArray
    local_heading: FloatArray
    low: FloatArray
    high: FloatArray
    nothing: FloatArray  # k×1
    cos_half: FloatArray  # M×1
    edge_offsets: FloatArray  # M×2: the sector's two edges relative to its heading
    circle_index: npt.NDArray[np.intp]  # M×C, or 1×K for every circle
    radii: FloatArray  # same shape
    radii_sq: FloatArray  # M×1×C (or 1×1×K)
    own_body: npt.NDArray[np.bool_] | None
    seg_index: npt.NDArray[np.intp] | None  # M×S


class ConeSensors:
    """The cone-model proximity sensors of the robots ``robots`` (indices into the world).

    ``static_circles`` are (x, y, r) of round obstacles; every robot's body is a circle of
    its profile's ``body_radius`` at its pose; ``seg_start``/``seg_vector`` (K×2) are
    every static segment, ``polygons`` and ``walls`` say which belong to what, for the
    broad phase. A robot never sees its own body.
    """

    def __init__(
        self,
        profiles: Sequence[RobotProfile],
        robots: Sequence[int],
        *,
        static_circles: Sequence[tuple[float, float, float]],
        seg_start: FloatArray,
        seg_vector: FloatArray,
        polygons: Sequence[PolygonBound],
        walls: Sequence[WallSegment],
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
        self.nothing_raw = 0.0  # what a calibrated e-puck sends with nothing in front
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
        # circle and segment tables, with the far padding entry last; robot centres are
        # written each step
        k = k_static + self.n_robots
        self._k_static = k_static
        self._cx = np.full(k + 1, _FAR)
        self._cy = np.full(k + 1, _FAR)
        self._cx[:k_static] = self.static[:, 0]
        self._cy[:k_static] = self.static[:, 1]
        self._radii = np.concatenate([self.static[:, 2], self.body_radii, [0.0]])
        self._seg_ax = np.append(self.seg_a[:, 0], _FAR)
        self._seg_ay = np.append(self.seg_a[:, 1], _FAR)
        self._seg_ex = np.append(self.seg_e[:, 0], 0.0)
        self._seg_ey = np.append(self.seg_e[:, 1], 0.0)
        self._plans: dict[Any, _Plan] = {}
        # A cone sees nothing beyond prox_max_distance from its apex, so that plus the
        # apex's offset from the centre is a cone robot's reach (widened by a hair so that
        # rounding never leaves out an object at exactly that distance).
        reach = [
            max(math.hypot(q.x, q.y) for q in p.prox_poses)
            + p.prox_max_distance * (1.0 + 1e-9)
            + 1e-9
            for p in cone
        ]
        #: which objects each cone robot may see
        self.broad_phase = SensorBroadPhase(
            [int(i) for i in robots],
            reach,
            self.body_radii.tolist(),
            static_circles=static_circles,
            polygons=polygons,
            walls=walls,
            n_segments=len(self.seg_a),
        )

    # -- the step ------------------------------------------------------------------------------
    def sense(
        self,
        poses: Sequence[Sequence[float]],
        distance: FloatArray,
        raw: FloatArray,
        *,
        every_object: bool = False,
    ) -> None:
        """Write the cone robots' rows of ``distance`` (N×8 m) and ``raw`` for ``poses``.

        The broad phase says which cone robots have anything within reach; the others
        read nothing without a single geometric test, which is most steps of a
        line-following run. The rest test only the circles (static ones first, then
        robots) and segments it found for them. A nearest distance is a minimum over
        objects, and an object left out lies beyond every sensor's reach, so the readings
        are those of testing every object, which ``every_object`` does (every cone robot
        against everything: what the tests compare with).
        """
        if not len(self.robots):
            return
        rows = self._rows  # a slice when every robot is a cone robot: cheaper to assign
        distance[rows] = self.nothing
        raw[rows] = self.nothing_raw
        candidates: Mapping[int, tuple[tuple[int, ...], tuple[int, ...]]] | None
        if every_object:
            picked = list(range(len(self.robots)))
            candidates = None
        else:
            candidates = self.broad_phase.candidates(poses)
            if not candidates:
                return  # nothing within any cone robot's reach (most steps)
            cone_index = self._cone_index
            picked = [cone_index[i] for i in candidates]
        plan = self._plan(picked, candidates)
        k_static = self._k_static
        if candidates is None:
            for i in range(self.n_robots):
                self._cx[k_static + i], self._cy[k_static + i] = poses[i][0], poses[i][1]
        else:
            for c in {c for i in plan.chosen_list for c in candidates[i][0]}:
                if c >= k_static:
                    pose = poses[c - k_static]
                    self._cx[c], self._cy[c] = pose[0], pose[1]
        own = np.array([poses[i] for i in plan.chosen_list], dtype=float)
        c, s = np.cos(own[:, 2:3]), np.sin(own[:, 2:3])
        apex_x = (own[:, 0:1] + c * plan.local_x - s * plan.local_y).reshape(-1)
        apex_y = (own[:, 1:2] + s * plan.local_x + c * plan.local_y).reshape(-1)
        heading = (own[:, 2:3] + plan.local_heading).reshape(-1)
        nearest = self._circles(plan, apex_x, apex_y, heading)
        if plan.seg_index is not None:
            nearest = np.minimum(nearest, self._segments(plan, apex_x, apex_y, heading))
        reading = np.where((nearest >= plan.low) & (nearest <= plan.high), nearest, np.inf)
        reading = reading.reshape(-1, 8)
        seen = np.isfinite(reading)
        distance[plan.chosen] = np.where(seen, reading, plan.nothing)
        raw[plan.chosen] = np.where(seen, calibrated_from_distance(reading), self.nothing_raw)

    def _plan(
        self,
        picked: list[int],
        candidates: Mapping[int, tuple[tuple[int, ...], tuple[int, ...]]] | None,
    ) -> _Plan:
        """The arrays for these active robots and candidates, cached: the set changes only
        every few dozen steps."""
        chosen_list = tuple(int(self.robots[c]) for c in picked)
        key: Any = (
            chosen_list
            if candidates is None
            else tuple((i, candidates[i][0], candidates[i][1]) for i in chosen_list)
        )
        plan = self._plans.get(key)
        if plan is not None:
            return plan
        active = np.array(picked, dtype=np.intp)
        sensors = (active[:, None] * 8 + np.arange(8)).reshape(-1)
        half = self.half[sensors]
        if candidates is None:
            circle_index = np.arange(self._k_static + self.n_robots)[None, :]
            own_body: npt.NDArray[np.bool_] | None = self.own_body[sensors]
            seg_index = np.arange(len(self.seg_a))[None, :] if len(self.seg_a) else None
        else:
            circle_index = _padded([candidates[i][0] for i in chosen_list], len(self._cx) - 1)
            own_body = None
            segs = [candidates[i][1] for i in chosen_list]
            seg_index = _padded(segs, len(self._seg_ax) - 1) if any(segs) else None
        radii = self._radii[circle_index]
        plan = _Plan(
            chosen=np.array(chosen_list, dtype=np.intp),
            chosen_list=chosen_list,
            local_x=self.local_x[active],
            local_y=self.local_y[active],
            local_heading=self.local_heading[active],
            low=self.min_distance[sensors],
            high=self.max_distance[sensors],
            nothing=self.nothing[active],
            cos_half=self.cos_half[sensors][:, None],
            edge_offsets=np.stack([-half, half], axis=1),
            circle_index=circle_index,
            radii=radii,
            radii_sq=(radii * radii)[:, None, :],
            own_body=own_body,
            seg_index=seg_index,
        )
        if len(self._plans) > 1024:
            self._plans.clear()
        self._plans[key] = plan
        return plan

    def _circles(
        self, plan: _Plan, apex_x: FloatArray, apex_y: FloatArray, heading: FloatArray
    ) -> FloatArray:
        """M nearest in-sector distances to any candidate circle (inf where none is inside)."""
        if plan.circle_index.shape[1] == 0:
            return np.full(len(apex_x), np.inf)
        vx = self._cx[plan.circle_index] - apex_x[:, None]  # M×C
        vy = self._cy[plan.circle_index] - apex_y[:, None]
        radii = plan.radii
        dist = np.hypot(vx, vy)
        ux, uy = np.cos(heading)[:, None], np.sin(heading)[:, None]
        # the circle's nearest point lies along the direction to its centre
        towards = vx * ux + vy * uy >= dist * plan.cos_half
        best = np.where(towards, np.maximum(dist - radii, 0.0), np.inf)
        best = np.where(dist <= radii, 0.0, best)  # the sensor inside the circle
        # both edges of the sector at once (axis 1): where each first enters the circle
        edges = heading[:, None] + plan.edge_offsets  # M×2
        bx, by = np.cos(edges)[:, :, None], np.sin(edges)[:, :, None]
        along = vx[:, None, :] * bx + vy[:, None, :] * by  # M×2×C
        disc = plan.radii_sq - ((dist * dist)[:, None, :] - along * along)
        root = np.sqrt(np.maximum(disc, 0.0))
        enters = (disc >= 0.0) & (along + root >= 0.0)
        on_edges = np.where(enters, np.maximum(along - root, 0.0), np.inf).min(axis=1)
        best = np.minimum(best, on_edges)
        if plan.own_body is not None:
            best[plan.own_body] = np.inf
        return best.min(axis=1)  # type: ignore[no-any-return]

    def _segments(
        self, plan: _Plan, apex_x: FloatArray, apex_y: FloatArray, heading: FloatArray
    ) -> FloatArray:
        """M nearest in-sector distances to any candidate segment (inf where none is inside)."""
        index = plan.seg_index
        assert index is not None
        ax = self._seg_ax[index] - apex_x[:, None]  # segment start relative to the apex
        ay = self._seg_ay[index] - apex_y[:, None]
        ex, ey = self._seg_ex[index], self._seg_ey[index]
        ux, uy = np.cos(heading)[:, None], np.sin(heading)[:, None]
        cos_half = plan.cos_half
        half = plan.edge_offsets[:, 1]

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
        return best.min(axis=1)  # type: ignore[no-any-return]


def _padded(lists: list[tuple[int, ...]], pad: int) -> npt.NDArray[np.intp]:
    """Each robot's candidate list repeated for its 8 sensors (M rows), padded with ``pad``."""
    width = max(len(c) for c in lists)
    out = np.full((8 * len(lists), width), pad, dtype=np.intp)
    for r, c in enumerate(lists):
        out[8 * r : 8 * r + 8, : len(c)] = c
    return out
