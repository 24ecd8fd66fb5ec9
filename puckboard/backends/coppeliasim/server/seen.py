"""What a proximity sensor sees: the object, the point and the surface normal.

``sim.readProximitySensor`` answers with more than a distance: the detected point (in
the sensor's frame), the handle of the object it belongs to and the surface normal
there. Clients use the handle to tell another robot from an obstacle or a wall, so the
server must know *which* object is nearest, which the simulation's vectorised sensing
(all sensors at once, distances only) does not keep. This module answers that question
for one sensor, when a client asks, with the V-REP semantics of the cone model: the
nearest point of any object inside the sensor's sector (apex at the sensor, opening its
profile's aperture), by exact geometry, in plain Python (a handful of objects, once per
call).

The world's reading stays the authority on *whether* and *how far* the sensor detects;
this only names the object and the direction to it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ....profile import RobotProfile
    from ....scenario.scene import Scene

__all__ = ["Seen", "nearest_in_sector"]

_SLACK = 1e-9  # rad: a point exactly on the sector's edge counts as inside

Point = tuple[float, float]


@dataclass(frozen=True)
class Seen:
    """The nearest thing in a sensor's sector: ``key`` names it (``("robot", j)``,
    ``("obstacle", k)`` or ``("wall", k)``), ``point`` is the nearest point (world, m),
    ``normal`` the outward surface normal there (world, unit), ``distance`` from the sensor."""

    key: tuple[str, int]
    point: Point
    normal: Point
    distance: float


def nearest_in_sector(
    scene: Scene,
    poses: Sequence[Sequence[float]],
    profiles: Sequence[RobotProfile],
    robot: int,
    sensor: int,
    *,
    reach: float | None = None,
) -> Seen | None:
    """The nearest object inside the sector of robot ``robot``'s IR sensor ``sensor``
    (the real robot's index, ps0..ps7), within ``reach`` (m; default the profile's
    ``prox_max_distance``) of it; ``None`` if nothing is there. The robot's own body is
    never seen."""
    from ....scenario.scene import CircleObstacle

    profile = profiles[robot]
    bx, by, bth = (float(v) for v in poses[robot][:3])
    q = profile.prox_poses[sensor]
    c, s = math.cos(bth), math.sin(bth)
    apex = (bx + c * q.x - s * q.y, by + s * q.x + c * q.y)
    look = bth + q.heading
    half = profile.prox_aperture / 2.0
    limit = profile.prox_max_distance if reach is None else reach
    sector = _Sector(apex, look, half)

    best: Seen | None = None

    def offer(key: tuple[str, int], hit: tuple[float, Point, Point] | None) -> None:
        nonlocal best
        if hit is not None and hit[0] <= limit and (best is None or hit[0] < best.distance):
            best = Seen(key, hit[1], hit[2], hit[0])

    for j, pose in enumerate(poses):
        if j != robot:
            offer(("robot", j), sector.circle((float(pose[0]), float(pose[1])),
                                              profiles[j].body_radius))  # fmt: skip
    for k, ob in enumerate(scene.obstacles):
        if isinstance(ob, CircleObstacle):
            offer(("obstacle", k), sector.circle((ob.x, ob.y), ob.radius))
        else:
            starts, vectors = ob.edges()
            for a, v in zip(starts.tolist(), vectors.tolist()):
                offer(("obstacle", k), sector.segment((a[0], a[1]), (a[0] + v[0], a[1] + v[1])))
    if scene.arena is not None:
        starts, vectors = scene.arena.edges()
        for k, (a, v) in enumerate(zip(starts.tolist(), vectors.tolist())):
            offer(("wall", k), sector.segment((a[0], a[1]), (a[0] + v[0], a[1] + v[1])))
    return best


class _Sector:
    """A 2-D sector: apex, the direction it looks (rad) and its half-opening (rad)."""

    def __init__(self, apex: Point, look: float, half: float) -> None:
        self.ax, self.ay = apex
        self.ux, self.uy = math.cos(look), math.sin(look)
        self.cos_half = math.cos(half + _SLACK)
        self.edges = [(math.cos(look + t), math.sin(look + t)) for t in (half, -half)]

    def inside(self, px: float, py: float) -> bool:
        dx, dy = px - self.ax, py - self.ay
        length = math.hypot(dx, dy)
        return length == 0.0 or (dx * self.ux + dy * self.uy) >= self.cos_half * length

    def circle(self, centre: Point, radius: float) -> tuple[float, Point, Point] | None:
        """Nearest point of a disc inside the sector: towards its centre when that lies
        in the sector, else where one of the sector's edges first enters it."""
        cx, cy = centre
        dx, dy = cx - self.ax, cy - self.ay
        length = math.hypot(dx, dy)
        if length <= radius:  # the sensor is inside the object
            return 0.0, (self.ax, self.ay), (-self.ux, -self.uy)
        if self.inside(cx, cy):
            t = length - radius
            px, py = self.ax + dx / length * t, self.ay + dy / length * t
            return t, (px, py), ((px - cx) / radius, (py - cy) / radius)
        best = None
        for ex, ey in self.edges:
            b = dx * ex + dy * ey
            disc = b * b - (length * length - radius * radius)
            if disc < 0.0:
                continue
            t = b - math.sqrt(disc)
            if t >= 0.0 and (best is None or t < best[0]):
                px, py = self.ax + ex * t, self.ay + ey * t
                best = (t, (px, py), ((px - cx) / radius, (py - cy) / radius))
        return best

    def segment(self, p: Point, q: Point) -> tuple[float, Point, Point] | None:
        """Nearest point of a segment inside the sector: its point nearest the apex, its
        ends, or where the sector's edges cross it, whichever is inside and nearest."""
        (px, py), (qx, qy) = p, q
        vx, vy = qx - px, qy - py
        length2 = vx * vx + vy * vy
        if length2 == 0.0:
            return None
        candidates: list[Point] = []
        t = ((self.ax - px) * vx + (self.ay - py) * vy) / length2
        t = min(1.0, max(0.0, t))
        candidates.append((px + t * vx, py + t * vy))
        candidates += [p, q]
        for ex, ey in self.edges:
            denom = ex * vy - ey * vx
            if denom == 0.0:
                continue
            wx, wy = px - self.ax, py - self.ay
            s = (wx * vy - wy * vx) / denom  # along the edge ray
            u = (wx * ey - wy * ex) / denom  # along the segment
            if s >= 0.0 and 0.0 <= u <= 1.0:
                candidates.append((self.ax + s * ex, self.ay + s * ey))
        best = None
        for cx, cy in candidates:
            if not self.inside(cx, cy):
                continue
            d = math.hypot(cx - self.ax, cy - self.ay)
            if best is None or d < best[0]:
                best = (d, (cx, cy))
        if best is None:
            return None
        nx, ny = -vy, vx  # a normal of the segment, turned to face the sensor
        norm = math.sqrt(length2)
        nx, ny = nx / norm, ny / norm
        if (self.ax - best[1][0]) * nx + (self.ay - best[1][1]) * ny < 0.0:
            nx, ny = -nx, -ny
        return best[0], best[1], (nx, ny)
