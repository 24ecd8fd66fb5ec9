"""The judge: scores a run from robot poses, whatever simulator produced them.

The judge is fed, once per control cycle, the time and every robot's pose (x, y, theta
in the world frame) and, when the simulator counts them, each robot's cumulative
collision count. Poses may be the embedded world's ground truth or poses read through
CoppeliaSim's API: the judge knows nothing else about the backend.

Per robot it measures

* **progress** along the track in the robot's *starting* direction (m, reported in
  laps): the pose is projected onto the track polyline's arc length and unwrapped. The
  projection is only trusted while the robot is within ``near_line`` of the line; off
  the line (avoiding an obstacle) the last arc position is held, and the detour's net
  progress is added when the robot comes back;
* **distance driven** (the path length of its centre);
* **collisions** (the simulator's count, else geometric contacts: body against body,
  obstacle or wall, counted at each new contact);
* **on-line fraction**: the share of cycles with the line under the ground-sensor bar
  (the point between the ground sensors within half the line's width plus the outer
  sensors' offset of the line);
* **obstacles passed**: an obstacle standing on the line is passed when the robot's
  track position gets ``pass_margin`` beyond the obstacle's arc position while the robot
  is back on the line;
* **passed the other robot**: the order of two robots along the line has swapped
  (they met and went past each other), judged only while both are near the line.

Outcomes (``Goal.kind`` of the scene; thresholds in :class:`JudgeRules`):

``pass``  success once every pair of robots has passed, every robot has passed every
          obstacle on the line, nothing collided, and every robot has been on the line
          and moving forward in its starting direction for ``settle_s``.
``follow`` success once every robot has ``goal.laps`` laps of progress.
``avoid`` success when the run ends with no collision and no robot stuck.

Failures. Every failure the judge detects is kept, once per kind, in order of detection
(:attr:`Judge.failures`). After the first one the judge keeps watching for
``failure_watch_s``, because one failure often leads into another: two robots that touch
and then drive off side by side are the thesis's Figure 4.6, which a report of
``collision`` alone would hide. The reported :attr:`Judge.failure` is ``parallel_driving``
when it was detected (it names the thesis's phenomenon), else the first failure detected.
The outcome is final at ``parallel_driving``, when the watch ends, or at the end of the run.

``collision``        a robot touched another robot, an obstacle or a wall;
``parallel_driving`` two robots drove side by side, close and heading the same way, for
                     ``parallel_s`` (the thesis's Figure 4.6);
``stuck``            a robot's centre moved less than ``stuck_distance`` in ``stuck_s``;
``turned_back``      a robot went ``turn_back_m`` back along the line against its starting
                     direction;
``lost_line``        a robot was off the line for ``lost_line_s`` without a break;
``not_passed``       (at the end) the robots never went past each other;
``obstacles_not_passed`` (at the end) a robot had not passed every obstacle on the line;
``timeout``          (at the end) anything else the goal asks for was not reached in time.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from ..geometry import project_on_segments
from ..profile import get_profile, profile_values
from .scene import CircleObstacle, PolygonObstacle, Scene
from .track_position import NearestSegment, TrackProjector

__all__ = ["FAILURES", "Event", "Judge", "JudgeRules", "RobotMetrics"]

FAILURES: dict[str, str] = {
    "collision": "a robot touched another robot, an obstacle or a wall",
    "parallel_driving": "two robots drove side by side in the same direction (thesis Figure 4.6)",
    "stuck": "a robot hardly moved for a long time",
    "turned_back": "a robot followed the line back against its starting direction",
    "lost_line": "a robot was off the line for too long",
    "not_passed": "the robots never went past each other",
    "obstacles_not_passed": "a robot had not passed every obstacle on the line by the end",
    "timeout": "the run ended before the goal was reached",
}
"""Every failure name the judge can report, with its meaning."""

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class JudgeRules:
    """Thresholds of the judge; the defaults are argued in docs/scenarios.md."""

    near_line: float = 0.10  # m: within this the track projection is trusted
    on_line_margin: float = 0.012  # m beyond half the line width (outer ground sensors at 1 cm)
    pass_margin: float = 0.05  # m beyond the crossing point before a pass counts
    obstacle_on_track: float = 0.03  # m: an obstacle this close to the line stands on it
    settle_s: float = 3.0  # s on the line moving forward before success is final
    parallel_distance: float = 0.12  # m between centres (bodies 4.6 cm apart: in IR range)
    parallel_heading_deg: float = 45.0  # max heading difference to count as "same way"
    parallel_s: float = 3.0  # s of side-by-side driving that make it a failure
    moving_speed: float = 0.01  # m/s: slower than this is not "driving"
    stuck_s: float = 10.0  # s window for the stuck test
    stuck_distance: float = 0.02  # m: less net movement than this in stuck_s is stuck
    turn_back_m: float = 0.25  # m back along the line below the best progress so far
    lost_line_s: float = 25.0  # s continuously off the line
    debounce_s: float = 0.5  # s a line state must last before left_line/back_on_line
    failure_watch_s: float = 10.0  # s after the first failure still watched for others


@dataclass(frozen=True)
class Event:
    """Something the judge noticed: ``kind`` happened to ``robot`` at ``time_s``."""

    time_s: float
    robot: str
    kind: str

    def to_dict(self) -> dict[str, Any]:
        return {"time_s": round(self.time_s, 3), "robot": self.robot, "kind": self.kind}


@dataclass
class RobotMetrics:
    """What the judge measured for one robot."""

    name: str
    progress_laps: float = 0.0
    distance_m: float = 0.0
    collisions: int = 0
    on_line_fraction: float = 0.0
    obstacles_passed: int = 0
    passed_other: bool = False
    profile: str = ""
    #: the robot's true value of every uncertain number (``--set profile.PATH=VALUE``)
    profile_values: dict[str, float] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "profile": self.profile,
            "profile_values": dict(self.profile_values),
            "progress_laps": round(self.progress_laps, 4),
            "distance_m": round(self.distance_m, 4),
            "collisions": self.collisions,
            "on_line_fraction": round(self.on_line_fraction, 4),
            "obstacles_passed": self.obstacles_passed,
            "passed_other": self.passed_other,
        }


@dataclass
class _RobotState:
    name: str
    radius: float
    sensor_offset: float
    sign: float = 1.0  # +1: starts along the track direction, -1: against it
    arc: float = 0.0  # last trusted arc position (m, in [0, L))
    unwrapped: float = 0.0  # arc position unwrapped (m, track direction)
    progress: float = 0.0  # m in the starting direction
    best_progress: float = 0.0
    distance: float = 0.0
    collisions: int = 0
    sim_collisions: int = 0
    on_line_cycles: int = 0
    cycles: int = 0
    near: bool = False
    on_line: bool = False
    line_state: bool = True  # debounced, as reported by events
    line_candidate: bool = True
    line_candidate_since: float = 0.0
    off_line_since: float | None = None
    on_line_since: float | None = None
    obstacle_k0: list[int] = field(default_factory=list)
    obstacle_k: list[int] = field(default_factory=list)
    history: deque[tuple[float, float, float, float]] = field(default_factory=deque)
    #: the positions (time, x, y) of the stuck test's window, oldest first
    window: deque[tuple[float, float, float]] = field(default_factory=deque)
    contacts: set[str] = field(default_factory=set)


class Judge:
    """Scores a run of ``scene``; feed it with :meth:`update`, end it with :meth:`finish`.

    ``rules`` overrides the thresholds. After every update, :attr:`decided` tells whether
    the outcome is final (:attr:`success`, :attr:`failure`).
    """

    def __init__(self, scene: Scene, *, rules: JudgeRules | None = None) -> None:
        self.scene = scene
        self.rules = rules or JudgeRules()
        self.goal = scene.goal.resolve(scene)
        self.names = tuple(r.name for r in scene.robots)
        self.n = len(self.names)
        self.time = 0.0
        self.started = False
        self.decided = False
        self.success: bool | None = None
        self.failure: str | None = None
        self.failure_robot: str = ""
        #: every failure detected, once per kind, in order of detection
        self.failures: list[str] = []
        #: when each of :attr:`failures` was detected (s)
        self.failure_times: dict[str, float] = {}
        self._failure_robots: dict[str, str] = {}
        self._first_failure_time: float | None = None
        self.events: list[Event] = []
        self.robots: list[_RobotState] = []
        # the judge sees the robots as built (their truth), not as their controllers believe
        profiles = [spec.actual or get_profile(spec.profile) for spec in scene.robots]
        self.profiles = tuple(p.name for p in profiles)
        self.profile_values = tuple(profile_values(p) for p in profiles)
        for spec, profile in zip(scene.robots, profiles):
            ground_x = float(np.mean([p.x for p in profile.ground_poses]))
            self.robots.append(_RobotState(spec.name, profile.body_radius, ground_x))
        track = scene.track
        projector = TrackProjector(track.segments(), track.closed) if track else None
        self.projector = projector
        # each robot's centre and sensor point, followed along the track cycle by cycle
        self._centres = [NearestSegment(projector) for _ in self.robots] if projector else []
        self._sensors = [NearestSegment(projector) for _ in self.robots] if projector else []
        self.length = self.projector.length if self.projector else 0.0
        self.on_line_tolerance = (track.width / 2 if track else 0.0) + self.rules.on_line_margin
        # obstacles standing on the line, with their arc positions
        self.track_obstacles: list[tuple[str, float]] = []
        self._circles: list[tuple[str, float, float, float]] = []
        self._edges: list[tuple[str, FloatArray, FloatArray, FloatArray]] = []
        for i, ob in enumerate(scene.obstacles):
            label = ob.name or f"obstacle{i + 1}"
            if isinstance(ob, CircleObstacle):
                centre = np.array([ob.x, ob.y])
                size = ob.radius
                self._circles.append((label, ob.x, ob.y, ob.radius))
            else:
                assert isinstance(ob, PolygonObstacle)
                centre = ob.vertices.mean(axis=0)
                size = float(np.max(np.linalg.norm(ob.vertices - centre, axis=1)))
                start, vec = ob.edges()
                self._edges.append((label, start, vec, ob.vertices))
            if self.projector is not None:
                arc, dist, _ = self.projector.project(centre[None, :])
                if dist[0] <= size + self.rules.obstacle_on_track:
                    self.track_obstacles.append((label, float(arc[0])))
        # pairs of robots: net number of times i went past j along the line
        self._pair_k0: dict[tuple[int, int], int] = {}
        self._pair_k: dict[tuple[int, int], int] = {}
        self._parallel_since: dict[tuple[int, int], float | None] = {}
        # how long a robot's positions are kept (the longest window that reads them)
        self._horizon = max(self.rules.stuck_s, self.rules.settle_s) + 1.0
        self._sim_counts: list[int] = [0] * self.n  # the simulator's collision counts

    # -- feeding ---------------------------------------------------------------------------
    def update(
        self,
        time: float,
        poses: npt.ArrayLike,
        collisions: npt.ArrayLike | None = None,
    ) -> None:
        """One observation: ``poses`` is N×3 (x, y, theta) in scene robot order;
        ``collisions`` (optional) the simulator's cumulative collision count per robot."""
        if type(poses) is np.ndarray and poses.shape == (self.n, 3) and poses.dtype == float:
            p = poses  # a simulator's pose array, as it is every cycle
        else:
            p = np.asarray(poses, dtype=float).reshape(self.n, 3)
        self.time = float(time)
        if not self.started:
            self._start(p)
        # a few robots: the per-robot bookkeeping below runs on plain floats, which cost
        # less than numpy's scalars and give the same values
        rows = p.tolist()
        self._track_update(p, rows)
        self._motion_update(rows)
        self._collision_update(rows, collisions)
        self._pair_update(rows)
        if not self.decided:
            self._decide()

    def _start(self, p: FloatArray) -> None:
        self.started = True
        for i, r in enumerate(self.robots):
            x, y, th = p[i]
            r.history.append((self.time, x, y, 0.0))
            r.window.append((self.time, float(x), float(y)))
            if self.projector is None:
                continue
            arc, dist, heading = self.projector.project(p[i : i + 1, :2])
            r.arc = float(arc[0])
            r.unwrapped = r.arc
            r.sign = 1.0 if math.cos(th - heading[0]) >= 0 else -1.0
            r.near = bool(dist[0] <= self.rules.near_line)
            margin = self.rules.pass_margin
            for _, s_o in self.track_obstacles:
                # an obstacle just behind the start (within the margin) is not "passed" at t=0
                k = math.floor((r.sign * (r.unwrapped - s_o) - margin) / self.length)
                r.obstacle_k0.append(k)
                r.obstacle_k.append(k)
        if self.projector is not None:
            for i in range(self.n):
                for j in range(i + 1, self.n):
                    k = math.floor(
                        (self.robots[i].unwrapped - self.robots[j].unwrapped) / self.length
                    )
                    self._pair_k0[(i, j)] = k
                    self._pair_k[(i, j)] = k
        for i in range(self.n):
            for j in range(i + 1, self.n):
                self._parallel_since[(i, j)] = None

    def _track_update(self, p: FloatArray, rows: list[list[float]]) -> None:
        if self.projector is None:
            for r in self.robots:
                r.cycles += 1
            return
        L = self.length
        arcs = self.projector.arcs
        near_line, tolerance = self.rules.near_line, self.on_line_tolerance
        closed = self.projector.closed
        # the point between the ground sensors: numpy's cos and sin, as ever
        theta = p[:, 2]
        cos = np.cos(theta).tolist()
        sin = np.sin(theta).tolist()
        for i, r in enumerate(self.robots):
            x, y, _ = rows[i]
            r.cycles += 1
            nearest = self._centres[i].query(x, y, near_line)
            r.near = nearest is not None
            offset = r.sensor_offset
            reach = abs(offset) + tolerance + 1e-6
            if nearest[2] > reach * reach if nearest is not None else near_line > reach:
                # the centre is farther than ``reach`` from the line, so the sensor point,
                # ``offset`` from it, is farther than the tolerance
                r.on_line = False
            else:
                sensor = (x + cos[i] * offset, y + sin[i] * offset)
                r.on_line = self._sensors[i].query(*sensor, tolerance) is not None
            if r.on_line:
                r.on_line_cycles += 1
            if nearest is not None:
                j, t, _ = nearest
                start, length = arcs[j]
                arc = start + t * length
                delta = arc - r.arc
                if closed:
                    delta = (delta + L / 2) % L - L / 2
                r.arc = arc
                r.unwrapped += delta
                r.progress += r.sign * delta
                r.best_progress = max(r.best_progress, r.progress)
            self._line_events(r)
            if r.on_line:
                self._obstacle_passes(r)

    def _line_events(self, r: _RobotState) -> None:
        now = self.time
        if r.on_line:
            r.off_line_since = None
            if r.on_line_since is None:
                r.on_line_since = now
        else:
            r.on_line_since = None
            if r.off_line_since is None:
                r.off_line_since = now
        if r.on_line != r.line_candidate:
            r.line_candidate = r.on_line
            r.line_candidate_since = now
        if (
            r.line_candidate != r.line_state
            and now - r.line_candidate_since >= self.rules.debounce_s
        ):
            r.line_state = r.line_candidate
            kind = "back_on_line" if r.line_state else "left_line"
            self.events.append(Event(r.line_candidate_since, r.name, kind))

    def _obstacle_passes(self, r: _RobotState) -> None:
        L = self.length
        h = self.rules.pass_margin
        for o, (_label, s_o) in enumerate(self.track_obstacles):
            q = r.sign * (r.unwrapped - s_o)
            k = r.obstacle_k[o]
            if q - h >= (k + 1) * L:
                r.obstacle_k[o] = k + 1
                if r.obstacle_k[o] - r.obstacle_k0[o] == 1:
                    self.events.append(Event(self.time, r.name, "passed_obstacle"))
            elif q + h < k * L:
                r.obstacle_k[o] = k - 1

    def _motion_update(self, p: list[list[float]]) -> None:
        horizon = self._horizon
        window = self.rules.stuck_s + 1e-9
        now = self.time
        for i, r in enumerate(self.robots):
            _, x0, y0, _ = r.history[-1]
            x, y = p[i][0], p[i][1]
            r.distance += math.hypot(x - x0, y - y0)
            r.history.append((now, x, y, r.progress))
            while r.history and now - r.history[0][0] > horizon:
                r.history.popleft()
            r.window.append((now, x, y))
            while now - r.window[0][0] > window:
                r.window.popleft()

    def _collision_update(self, p: list[list[float]], collisions: npt.ArrayLike | None) -> None:
        if collisions is not None:
            if type(collisions) is np.ndarray and collisions.shape == (self.n,):
                counts = collisions.astype(int, copy=False).tolist()
            else:
                counts = np.asarray(collisions, dtype=int).reshape(self.n).tolist()
            if counts == self._sim_counts:
                return  # nothing new touched anything (most steps)
            self._sim_counts = counts
            for i, r in enumerate(self.robots):
                new = counts[i] - r.sim_collisions
                if new > 0:
                    r.collisions += new
                    self.events.append(Event(self.time, r.name, "collision"))
                r.sim_collisions = counts[i]
            return
        for i, r in enumerate(self.robots):
            now = self._contacts_of(i, p)
            fresh = now - r.contacts
            if fresh:
                r.collisions += len(fresh)
                self.events.append(Event(self.time, r.name, "collision"))
            r.contacts = now

    def _contacts_of(self, i: int, p: list[list[float]]) -> set[str]:
        """What robot ``i``'s body touches now (names), by geometry alone."""
        eps = 1e-4
        r = self.robots[i]
        x, y = p[i][0], p[i][1]
        out: set[str] = set()
        for j, other in enumerate(self.robots):
            if j != i and math.hypot(p[j][0] - x, p[j][1] - y) < r.radius + other.radius + eps:
                out.add(f"robot:{other.name}")
        for label, cx, cy, rad in self._circles:
            if math.hypot(cx - x, cy - y) < rad + r.radius + eps:
                out.add(label)
        for label, start, vec, vertices in self._edges:
            if _point_polygon_distance(x, y, start, vec, vertices) < r.radius + eps:
                out.add(label)
        a = self.scene.arena
        if a is not None:
            if x - a.xmin < r.radius + eps or a.xmax - x < r.radius + eps:
                out.add("wall")
            if y - a.ymin < r.radius + eps or a.ymax - y < r.radius + eps:
                out.add("wall")
        return out

    def _pair_update(self, p: list[list[float]]) -> None:
        rules = self.rules
        max_heading = math.radians(rules.parallel_heading_deg)
        for (i, j), since in self._parallel_since.items():
            ri, rj = self.robots[i], self.robots[j]
            # order along the line, only while both robots are near it
            if self.projector is not None and ri.near and rj.near:
                L = self.length
                diff = ri.unwrapped - rj.unwrapped
                k = self._pair_k[(i, j)]
                if diff - rules.pass_margin >= (k + 1) * L:
                    self._pair_k[(i, j)] = k + 1
                elif diff + rules.pass_margin < k * L:
                    self._pair_k[(i, j)] = k - 1
                if self._pair_k[(i, j)] != k and self._pair_passed(i, j):
                    self.events.append(Event(self.time, ri.name, "passed_other"))
                    self.events.append(Event(self.time, rj.name, "passed_other"))
            # side by side, close, same heading, both driving
            pi, pj = p[i], p[j]
            dx, dy = pj[0] - pi[0], pj[1] - pi[1]
            dist = math.hypot(dx, dy)
            dth = abs(_wrap(pj[2] - pi[2]))
            side_by_side = False
            if dist < rules.parallel_distance and dth < max_heading and dist > 0:
                mean = math.atan2(
                    math.sin(pi[2]) + math.sin(pj[2]), math.cos(pi[2]) + math.cos(pj[2])
                )
                lateral = abs(-math.sin(mean) * dx + math.cos(mean) * dy) / dist
                side_by_side = lateral > math.sin(math.radians(45.0))
            if side_by_side and self._moving(ri) and self._moving(rj):
                if since is None:
                    self._parallel_since[(i, j)] = self.time
            else:
                self._parallel_since[(i, j)] = None

    def _moving(self, r: _RobotState, window: float = 1.0) -> bool:
        """Whether the robot's centre moved at least ``moving_speed`` over the last second."""
        t, x, y, _ = r.history[-1]
        for t0, x0, y0, _ in reversed(r.history):
            if t - t0 >= window:
                return math.hypot(x - x0, y - y0) >= self.rules.moving_speed * (t - t0)
        return True  # not enough history yet: assume driving

    # -- deciding --------------------------------------------------------------------------
    def _fail(self, kind: str, robot: str, *, final: bool = False) -> None:
        """Record failure ``kind`` (once per kind) and pick the one to report."""
        if kind in self.failures:
            return
        self.failures.append(kind)
        self.failure_times[kind] = self.time
        self._failure_robots[kind] = robot
        if self._first_failure_time is None:
            self._first_failure_time = self.time
        self.success = False
        self.failure = (
            "parallel_driving" if "parallel_driving" in self.failures else self.failures[0]
        )
        self.failure_robot = self._failure_robots[self.failure]
        if final or kind == "parallel_driving":
            self.decided = True
        event = Event(self.time, robot, kind)
        if event not in self.events[-2 * self.n :]:  # a collision is already an event
            self.events.append(event)

    def _succeed(self) -> None:
        self.decided = True
        self.success = True
        self.failure = None
        self.events.append(Event(self.time, "", "success"))

    def _decide(self) -> None:
        rules = self.rules
        for r in self.robots:
            if r.collisions:
                self._fail("collision", r.name)
                break
        for (i, j), since in self._parallel_since.items():
            if since is not None and self.time - since >= rules.parallel_s:
                self._fail("parallel_driving", f"{self.robots[i].name},{self.robots[j].name}")
        for r in self.robots:
            if self._stuck(r):
                self._fail("stuck", r.name)
        if self.projector is not None and self.goal in ("pass", "follow"):
            for r in self.robots:
                if r.best_progress - r.progress >= rules.turn_back_m:
                    self._fail("turned_back", r.name)
            for r in self.robots:
                if (
                    r.off_line_since is not None
                    and self.time - r.off_line_since >= rules.lost_line_s
                ):
                    self._fail("lost_line", r.name)
        if self.failures:
            assert self._first_failure_time is not None
            if self.time - self._first_failure_time >= rules.failure_watch_s:
                self.decided = True
            return None
        if self.goal == "pass" and self._pass_complete():
            return self._succeed()
        if self.goal == "follow" and all(
            r.progress >= self.scene.goal.laps * self.length for r in self.robots
        ):
            return self._succeed()
        return None

    def _stuck(self, r: _RobotState) -> bool:
        """Every position of the last ``stuck_s`` lies within ``stuck_distance`` of the latest."""
        t, x, y, _ = r.history[-1]
        window = self.rules.stuck_s
        if t - r.history[0][0] < window - 1e-9:
            return False  # not enough history to cover the window yet
        # oldest first: a robot that moves is far from where it was a window ago, so the
        # first position of the window usually settles it
        stuck = self.rules.stuck_distance
        return all(math.hypot(x - xw, y - yw) < stuck for _, xw, yw in r.window)

    def _pass_complete(self) -> bool:
        if self.n >= 2 and not all(self._pair_passed(i, j) for (i, j) in self._pair_k):
            return False
        for r in self.robots:
            if any(k - k0 < 1 for k, k0 in zip(r.obstacle_k, r.obstacle_k0)):
                return False
            if r.on_line_since is None or self.time - r.on_line_since < self.rules.settle_s:
                return False
            if self._progress_over(r, self.rules.settle_s) <= 0.0:
                return False
        return True

    def _pair_passed(self, i: int, j: int) -> bool:
        return self._pair_k[(i, j)] != self._pair_k0[(i, j)]

    def _progress_over(self, r: _RobotState, window: float) -> float:
        t, _, _, prog = r.history[-1]
        for t0, _, _, p0 in reversed(r.history):
            if t - t0 >= window:
                return prog - p0
        return 0.0

    def finish(self) -> None:
        """The run is over: settle the outcome if nothing has decided it yet."""
        if self.decided:
            return
        if self.failures:  # still watching after a failure: what was seen is the verdict
            self.decided = True
            return
        if self.goal == "avoid":
            return self._succeed()
        if self.goal == "pass":
            if self.n >= 2 and not all(self._pair_passed(i, j) for (i, j) in self._pair_k):
                return self._fail("not_passed", "", final=True)
            for r in self.robots:
                if any(k - k0 < 1 for k, k0 in zip(r.obstacle_k, r.obstacle_k0)):
                    return self._fail("obstacles_not_passed", r.name, final=True)
        return self._fail("timeout", "", final=True)

    # -- results ---------------------------------------------------------------------------
    def metrics(self) -> list[RobotMetrics]:
        """Per-robot measurements so far, in scene order."""
        out = []
        for i, r in enumerate(self.robots):
            passed = any(self._pair_passed(*pair) for pair in self._pair_k if i in pair)
            out.append(
                RobotMetrics(
                    name=r.name,
                    progress_laps=r.progress / self.length if self.length else 0.0,
                    distance_m=r.distance,
                    collisions=r.collisions,
                    on_line_fraction=r.on_line_cycles / r.cycles if r.cycles else 0.0,
                    obstacles_passed=sum(
                        1 for k, k0 in zip(r.obstacle_k, r.obstacle_k0) if k - k0 >= 1
                    ),
                    passed_other=passed,
                    profile=self.profiles[i],
                    profile_values=self.profile_values[i],
                )
            )
        return out


def _wrap(angle: float) -> float:
    return (angle + math.pi) % (2 * math.pi) - math.pi


def _point_polygon_distance(
    x: float, y: float, start: FloatArray, vec: FloatArray, vertices: FloatArray
) -> float:
    """Distance from (x, y) to a convex polygon (0 inside)."""
    wx = x - start[:, 0]
    wy = y - start[:, 1]
    if np.all(vec[:, 0] * wy - vec[:, 1] * wx >= 0):  # left of every CCW edge: inside
        return 0.0
    len2 = np.maximum((vec**2).sum(axis=1), 1e-18)
    _, qx, qy = project_on_segments(wx, wy, vec[:, 0], vec[:, 1], len2=len2)
    return float(np.min(np.hypot(qx, qy)))
