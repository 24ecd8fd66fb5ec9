"""A scene as plain, validated data: floor, track, obstacles, walls, robots, noise.

Scenes are loaded from TOML or JSON files (see :mod:`puckboard.scenario.scenefile`) into
these frozen dataclasses; the simulator, the judge, the viewers and ``puckboard serve``
all read the same objects. Units are SI; colours are 0..255 RGB triples.

World frame: x to the right, y up, angles counter-clockwise from +x, seen from above.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from ..profile.link_cycles import CycleLatency
from ..profile.model import RobotProfile

__all__ = [
    "GOAL_KINDS",
    "Arena",
    "CircleObstacle",
    "Control",
    "Goal",
    "Noise",
    "PolygonObstacle",
    "RobotSpec",
    "Scene",
    "Track",
    "whole_steps",
]

Colour = tuple[int, int, int]


def _polygon_edges(
    vertices: npt.ArrayLike,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """A closed polygon's edges as (start points, edge vectors), K×2 each."""
    v = np.asarray(vertices, dtype=float)
    return v.copy(), np.roll(v, -1, axis=0) - v


@dataclass(frozen=True, eq=False)
class Track:
    """A dark line on the floor: a polyline of ``points`` (M×2, m) of ``width`` (m).

    ``closed`` joins the last point back to the first (a loop). ``contrast`` is the share
    of the line's brightness difference from the floor that the ground sensors see
    (1: the line as its colour says; lower: a glossy or worn tape, a grey floor, which
    reflect more of the sensors' IR than the colour suggests; 0: no line).
    """

    points: npt.NDArray[np.float64]
    width: float = 0.02
    closed: bool = True
    colour: Colour = (20, 20, 20)
    contrast: float = 1.0

    def __post_init__(self) -> None:
        pts = np.array(self.points, dtype=float, copy=True)
        if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 2:
            raise ValueError(
                f"track.points must be a list of at least 2 [x, y] pairs, got shape {pts.shape}"
            )
        if not np.all(np.isfinite(pts)):
            raise ValueError("track.points must be finite numbers")
        if not self.width > 0:
            raise ValueError(f"track.width must be positive (m), got {self.width}")
        if not 0.0 <= self.contrast <= 1.0:
            raise ValueError(f"track.contrast must lie in [0, 1], got {self.contrast}")
        pts.setflags(write=False)
        object.__setattr__(self, "points", pts)

    def segments(self) -> npt.NDArray[np.float64]:
        """The line's segments as an S×2×2 array of (start, end) points."""
        pts = self.points
        ends = np.roll(pts, -1, axis=0) if self.closed else pts[1:]
        starts = pts if self.closed else pts[:-1]
        return np.stack([starts, ends], axis=1)

    @property
    def length(self) -> float:
        seg = self.segments()
        return float(np.linalg.norm(seg[:, 1] - seg[:, 0], axis=1).sum())


@dataclass(frozen=True)
class CircleObstacle:
    """A static round obstacle (a cylinder seen from above).

    ``ir_reflectance`` scales the IR light it sends back against the surface the IR
    response curve was measured on (1); a black object sends back little (0.1 or less):
    the e-puck's IR hardly sees it. V-REP's cone sensors ignore it, as V-REP does.
    """

    x: float
    y: float
    radius: float
    colour: Colour = (200, 60, 40)
    name: str = ""
    ir_reflectance: float = 1.0

    def __post_init__(self) -> None:
        _check_reflectance(self.ir_reflectance)


def _check_reflectance(value: float) -> None:
    if not 0.0 <= value <= 1.0:
        raise ValueError(f"obstacle ir_reflectance must lie in [0, 1], got {value}")


@dataclass(frozen=True, eq=False)
class PolygonObstacle:
    """A static convex polygon obstacle; ``vertices`` (K×2, m) counter-clockwise;
    ``ir_reflectance`` as :class:`CircleObstacle`'s."""

    vertices: npt.NDArray[np.float64]
    colour: Colour = (200, 60, 40)
    name: str = ""
    ir_reflectance: float = 1.0

    def __post_init__(self) -> None:
        v = np.array(self.vertices, dtype=float, copy=True)
        if v.ndim != 2 or v.shape[1] != 2 or len(v) < 3:
            raise ValueError(
                f"polygon vertices must be at least 3 [x, y] pairs, got shape {v.shape}"
            )
        v.setflags(write=False)
        object.__setattr__(self, "vertices", v)
        _check_reflectance(self.ir_reflectance)

    def edges(self) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """The closed outline's edges as (start points, edge vectors), K×2 each."""
        return _polygon_edges(self.vertices)


@dataclass(frozen=True)
class Arena:
    """Rectangular walls enclosing [xmin, xmax] × [ymin, ymax] (m)."""

    xmin: float
    ymin: float
    xmax: float
    ymax: float
    colour: Colour = (120, 120, 130)

    def __post_init__(self) -> None:
        if not (self.xmax > self.xmin and self.ymax > self.ymin):
            raise ValueError(f"arena needs xmax > xmin and ymax > ymin, got {self}")

    def edges(self) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """The four walls as (start points, edge vectors), counter-clockwise from (xmin, ymin)."""
        corners = np.array(
            [
                [self.xmin, self.ymin],
                [self.xmax, self.ymin],
                [self.xmax, self.ymax],
                [self.xmin, self.ymax],
            ]
        )
        return _polygon_edges(corners)


@dataclass(frozen=True)
class Dummy:
    """A named point of the scene that nothing collides with and no sensor sees: a goal,
    a waypoint, a reference frame (CoppeliaSim's dummy object). ``x, y, z`` in m."""

    name: str
    x: float
    y: float
    z: float = 0.0


@dataclass(frozen=True)
class RobotSpec:
    """One robot: name, start pose (m, m, rad), controller spec, body colour, robot profile
    (:mod:`puckboard.profile`: a shipped one by name, ``epuck``, the physical robot, or
    ``epuck-vrep``, V-REP's model; or a :class:`~puckboard.profile.RobotProfile` with
    changes, from ``--set profile.*`` or a profile file).

    ``profile`` is what the robot is believed to be: its controller, odometry and unit
    conversions go by it. ``actual``, when given, is what it truly is (a robot drawn by
    ``--variation plausible``): the simulator simulates that one, and nothing the
    controller sees tells it the difference.
    """

    name: str
    x: float
    y: float
    theta: float
    controller: str = "improved"
    colour: Colour = (60, 160, 60)
    profile: str | RobotProfile = "epuck"
    actual: RobotProfile | None = None


@dataclass(frozen=True)
class Noise:
    """Noise levels; every draw comes from the simulation's one seeded generator.

    ``wheel_speed``: relative σ of each wheel's actual speed against the command (Enki
    uses 5 %). ``proximity``: relative σ of the raw IR value. ``ground``: absolute σ of
    the 0..1 ground value. ``start_jitter``: σ of the start position (m) and heading
    (rad), for robustness sweeps. ``gyro``: σ (rad/s) of white noise on each gyro
    reading; at 0 the gyro draws nothing, so a scene without it runs as before.
    ``gyro_bias``: a constant offset (rad/s) on every gyro reading, what is left of the
    zero-rate error after the robot's start-up calibration (no draw either).
    """

    wheel_speed: float = 0.0
    proximity: float = 0.0
    ground: float = 0.0
    start_jitter: float = 0.0
    gyro: float = 0.0
    gyro_bias: float = 0.0


@dataclass(frozen=True)
class Control:
    """The control loop's timing, apart from the physics step ``dt``.

    ``period`` (s): how often each controller ticks and a wheel command is sent; the
    physics keeps stepping at ``dt`` in between, so it must be a whole number of steps.
    ``None`` means one step, the thesis's synchronous stepping (V-REP at its default
    50 ms step, every tick seeing the step just taken).

    ``latency`` (s): the loop's delay, from the instant the sensors were read to the
    instant the command computed from them turns the wheels. On a link to a robot the
    host can time only the whole round trip (it shares no clock with the robot), so
    this is one number, the sum of the sensing's age and the command's way to the
    wheels; the simulator applies it on the wheel side (a layer sees the step just
    taken, its command acts ``latency`` later), which for a controller that reacts to
    what it senses is the same loop. It too must be a whole number of steps (0: none).
    The links' ranges and their sources: :mod:`puckboard.profile.links`.

    A real link also varies from cycle to cycle (:mod:`puckboard.profile.link_cycles`):
    ``cycle_latency``, when given, adds to ``latency`` each command's own latency drawn
    from that distribution (the sum rounded to whole steps; a command never overtakes
    the one before it, as on one connection), and ``repeated`` is the share of cycles
    whose reading repeats the previous one, no new packet having come (its age grows).
    ``link`` names the link they were drawn from, for reports.
    """

    period: float | None = None
    latency: float = 0.0
    cycle_latency: CycleLatency | None = None
    repeated: float = 0.0
    link: str = ""

    def __post_init__(self) -> None:
        if not (math.isfinite(self.repeated) and 0.0 <= self.repeated < 1.0):
            raise ValueError(f"control.repeated must be a share in [0, 1), got {self.repeated!r}")

    @property
    def varies(self) -> bool:
        """Whether the loop varies from cycle to cycle (a latency drawn per command, or
        repeated readings)."""
        return self.cycle_latency is not None or self.repeated > 0.0

    @property
    def needs_link(self) -> bool:
        """Whether running this loop needs a simulated link: a latency, or a loop that
        varies from cycle to cycle (only a backend that simulates the link can run it)."""
        return self.latency > 0 or self.varies

    def is_default(self, dt: float) -> bool:
        """True for today's loop: one tick per physics step and no delay."""
        return (
            self.latency == 0.0
            and not self.varies
            and (self.period is None or _same(self.period, dt))
        )

    def period_for(self, dt: float) -> float:
        """The control period (s) with physics step ``dt``."""
        return dt if self.period is None else self.period

    @classmethod
    def rounded(cls, period: float, latency: float, dt: float) -> Control:
        """The loop at ``period`` and ``latency`` (s) as the simulator can run it: each
        rounded to the nearest whole number of physics steps of ``dt`` (the period to
        one step at least), by :func:`whole_steps`."""
        return cls(period=whole_steps(period, dt, minimum=1), latency=whole_steps(latency, dt))

    def steps(self, dt: float) -> tuple[int, int]:
        """(steps per tick, steps of latency) with physics step ``dt``; ``ValueError``
        (one line, saying how to fix it) for a period or latency that is negative, not
        finite, or not a whole number of steps."""
        # the settings that set them are named control.<field> (scenario.settings)
        return (
            _whole_steps("period", self.period_for(dt), dt, minimum=1),
            _whole_steps("latency", self.latency, dt, minimum=0),
        )


def whole_steps(seconds: float, dt: float, *, minimum: int = 0) -> float:
    """``seconds`` rounded to the nearest whole number of physics steps of ``dt`` (at least
    ``minimum`` steps), in seconds: the one rounding of a time the simulator takes in
    whole steps (a link's drawn or measured timing, a family's slow end)."""
    return max(minimum, round(seconds / dt)) * dt


def _same(a: float, b: float) -> bool:
    return abs(a - b) <= 1e-9 * max(abs(a), abs(b), 1e-12)


def _whole_steps(field: str, value: float, dt: float, *, minimum: int) -> int:
    """``value`` (s) as a whole number of physics steps of ``dt``, at least ``minimum``;
    ``field`` names the setting (``control.<field>``) in the one-line error."""
    name = f"control.{field}"
    if not math.isfinite(value) or value < 0 or (minimum and value <= 0):
        bound = "positive" if minimum else "zero or positive"
        raise ValueError(f"{name} must be a finite, {bound} number of seconds, got {value!r}")
    ratio = value / dt
    steps = round(ratio)
    if abs(ratio - steps) > 1e-6 or steps < minimum:
        below, above = math.floor(ratio), max(minimum, math.ceil(ratio))
        near = [f"{k * dt:g}" for k in sorted({max(minimum, below), above})]
        raise ValueError(
            f"{name} = {value:g} s is not a whole number of physics steps of dt = {dt:g} s "
            f"(the physics steps at dt between ticks); use {' or '.join(near)} s, or change dt"
        )
    return steps


GOAL_KINDS = ("auto", "pass", "follow", "avoid")
"""What a scene asks of its robots; the judge (:mod:`puckboard.scenario.judge`) scores it.

``pass``: robots on a line meet, pass each other and every obstacle on the line, and
go on following the line. ``follow``: follow the line for ``laps`` laps. ``avoid``:
roam for the whole run without touching anything. ``auto`` picks ``pass`` for a track
with two or more robots, ``follow`` for a track with one, ``avoid`` without a track.
"""


@dataclass(frozen=True)
class Goal:
    """The task a scene sets (``kind``, one of :data:`GOAL_KINDS`) and, for ``follow``,
    how many ``laps`` make a success."""

    kind: str = "auto"
    laps: float = 1.0

    def __post_init__(self) -> None:
        if self.kind not in GOAL_KINDS:
            raise ValueError(f"goal kind must be one of {', '.join(GOAL_KINDS)}, got {self.kind!r}")

    def resolve(self, scene: Scene) -> str:
        """The concrete goal kind for ``scene`` (``auto`` resolved)."""
        if self.kind != "auto":
            return self.kind
        if scene.track is None:
            return "avoid"
        return "pass" if len(scene.robots) >= 2 else "follow"


@dataclass(frozen=True)
class Scene:
    """Everything the simulator needs to build a world; see the module docstring."""

    name: str
    robots: tuple[RobotSpec, ...]
    track: Track | None = None
    obstacles: tuple[CircleObstacle | PolygonObstacle, ...] = ()
    arena: Arena | None = None
    noise: Noise = field(default_factory=Noise)
    dt: float = 0.05
    duration: float = 120.0
    description: str = ""
    floor_colour: Colour = (235, 235, 225)
    camera_size: tuple[int, int] = (52, 39)  # (width, height) pixels
    goal: Goal = field(default_factory=Goal)
    dummies: tuple[Dummy, ...] = ()
    #: the control loop's timing (default: one tick per step, no delay)
    control: Control = field(default_factory=Control)
    #: Where the scene was read from (a file's path, a shipped scene's file name), so a
    #: message about one of its robots can name the file; not part of what it describes.
    source: str = field(default="", compare=False)
    #: For a generated scene (a file with a ``[generate]`` table): the file's data as
    #: JSON, from which each episode's seed draws its own track (:mod:`.generated`); this
    #: scene is then seed 0's. None for a scene that is what it says.
    generate: str | None = field(default=None, compare=False, repr=False)

    def with_profile(self, profile: str | RobotProfile) -> Scene:
        """This scene with every robot given robot profile ``profile`` (a shipped one by
        name, or a profile); a truth drawn for the old profile goes with it."""
        robots = tuple(dataclasses.replace(r, profile=profile, actual=None) for r in self.robots)
        return dataclasses.replace(self, robots=robots)

    def robot(self, name: str) -> RobotSpec:
        for r in self.robots:
            if r.name == name:
                return r
        raise KeyError(
            f"scene {self.name!r} has no robot {name!r}; robots: {[r.name for r in self.robots]}"
        )
