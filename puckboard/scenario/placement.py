"""What stands in a scene: robots, obstacles and dummies, placed by coordinates or on the track.

Working out the coordinates of "a quarter of the way round the stadium" by hand is
error-prone, so a robot or an obstacle may be placed *on the track* by a fraction of the
lap (``track_position = 0.25``) or a distance along it (``track_distance``), plus a
sideways ``offset``; a robot may then face ``along`` or ``against`` the track instead of
giving ``theta``. :class:`TrackFrame` answers where such a position is;
:func:`read_robot`, :func:`read_obstacle` and :func:`read_dummy` read one table each and
return the scene's own objects, in SI units and radians.
"""

from __future__ import annotations

import math

import numpy as np

from ..profile import RobotProfile
from .reader import TableReader
from .robot_profiles import read_robot_profiles
from .scene import Arena, CircleObstacle, Dummy, PolygonObstacle, RobotSpec, Track

__all__ = [
    "DUMMY_KEYS",
    "OBSTACLE_KEYS",
    "ROBOT_KEYS",
    "TrackFrame",
    "place",
    "read_dummy",
    "read_obstacle",
    "read_robot",
]

#: Robots' default colours, in order, repeating.
ROBOT_COLOURS = ((60, 160, 60), (60, 90, 200), (220, 160, 30), (160, 60, 160))
OBSTACLE_SHAPES = ("circle", "box", "polygon")
#: Where something stands: by coordinates, or on the track (plus a sideways offset).
PLACE_KEYS = ("x", "y", "track_position", "track_distance", "offset")
#: The keys each table may have (an unknown one is refused before anything is read).
ROBOT_KEYS = frozenset(
    PLACE_KEYS
    + ("name", "theta", "theta_deg", "direction", "controller", "profile", "actual", "colour")
)
OBSTACLE_KEYS = frozenset(
    PLACE_KEYS
    + ("shape", "name", "colour", "radius", "size", "angle", "angle_deg", "vertices")
    + ("ir_reflectance",)
)
DUMMY_KEYS = frozenset(PLACE_KEYS + ("name", "z"))


class TrackFrame:
    """Arc-length positions on a track: where is 'a quarter of the way round'."""

    def __init__(self, track: Track) -> None:
        seg = track.segments()
        self.starts = seg[:, 0]
        self.vectors = seg[:, 1] - seg[:, 0]
        lengths = np.linalg.norm(self.vectors, axis=1)
        self.cumulative = np.concatenate([[0.0], np.cumsum(lengths)])
        self.length = float(self.cumulative[-1])

    def at(self, fraction: float) -> tuple[float, float, float]:
        """(x, y, heading of the track direction) at ``fraction`` of the length."""
        s = (fraction % 1.0) * self.length
        i = int(
            np.clip(np.searchsorted(self.cumulative, s, side="right") - 1, 0, len(self.starts) - 1)
        )
        seg_len = self.cumulative[i + 1] - self.cumulative[i]
        t = 0.0 if seg_len == 0 else (s - self.cumulative[i]) / seg_len
        p = self.starts[i] + t * self.vectors[i]
        heading = math.atan2(self.vectors[i][1], self.vectors[i][0])
        return float(p[0]), float(p[1]), heading


def place(reader: TableReader, frame: TrackFrame | None, what: str) -> tuple[float, float, float]:
    """(x, y, track heading) from ``x``/``y``, or on the track from ``track_position``
    (fraction of the lap) or ``track_distance`` (m from the start), plus ``offset``."""
    on_track = [k for k in ("track_position", "track_distance") if reader.has(k)]
    if on_track:
        return _place_on_track(reader, frame, on_track)
    # A value that is there but wrong is reported before one that is missing: for
    # x = "xx" without y, "x: expected a number" is the mistake to fix first.
    given_x = reader.number("x", unit="m") if reader.has("x") else None
    given_y = reader.number("y", unit="m") if reader.has("y") else None
    if given_x is None or given_y is None:
        reader.fail(
            "x" if given_x is None else "y",
            "",
            message=f"missing; {_a(what)} needs numbers x and y (m), or track_position "
            "or track_distance",
        )
    assert given_x is not None and given_y is not None
    return given_x, given_y, 0.0


def _place_on_track(
    reader: TableReader, frame: TrackFrame | None, on_track: list[str]
) -> tuple[float, float, float]:
    key = on_track[0]
    if len(on_track) > 1:
        reader.fail(key, "", message="give either track_position or track_distance")
    if reader.has("x") or reader.has("y"):
        reader.fail(key, "", message=f"give either x and y, or {key}")
    if frame is None:
        reader.fail(key, "", message="the scene has no [track] to place on")
    assert frame is not None
    if key == "track_position":
        fraction = reader.number(key, unit="fraction of the lap", low=0.0, high=1.0)
    else:
        fraction = reader.number(key, unit="m along the track from its start") / frame.length
    x, y, heading = frame.at(fraction)
    offset = reader.number("offset", 0.0, unit="m to the left of the track", low=-1.0, high=1.0)
    x -= offset * math.sin(heading)
    y += offset * math.cos(heading)
    return x, y, heading


def _a(noun: str) -> str:
    """``noun`` with its indefinite article: "an obstacle", "a robot"."""
    return f"{'an' if noun[:1].lower() in 'aeiou' else 'a'} {noun}"


def read_robot(
    reader: TableReader,
    index: int,
    frame: TrackFrame | None,
    default_profile: str | RobotProfile,
    arena: Arena | None = None,
) -> RobotSpec:
    """One ``[[robots]]`` table; ``default_profile`` is the scene's. A robot must start
    inside the ``arena``'s walls, when there are walls."""
    name = reader.string("name", f"epuck{index + 1}")
    if not name.strip():
        reader.fail("name", "a non-empty name", name)
    x, y, track_heading = place(reader, frame, "robot")
    if arena is not None:
        _inside(reader, arena, name, x, y)
    theta = _robot_heading(reader, track_heading)
    theta = math.atan2(math.sin(theta), math.cos(theta))  # wrapped to (-π, π]
    controller = reader.string("controller", "improved")
    if not controller.strip():
        reader.fail(
            "controller", "a controller spec such as improved, stock or module:factory", controller
        )
    profile, actual = read_robot_profiles(reader, default_profile)
    colour = reader.colour("colour", ROBOT_COLOURS[index % len(ROBOT_COLOURS)])
    reader.finish()
    return RobotSpec(
        name, x, y, theta, controller=controller, colour=colour, profile=profile, actual=actual
    )


def _inside(reader: TableReader, arena: Arena, name: str, x: float, y: float) -> None:
    """Refuse a start outside the walls: the engine would push the robot back through the
    wall by however far it is out (metres, for a typo), and the run would go on as if
    nothing had happened. A centre inside whose body touches a wall is only moved clear,
    with a warning, like any start that overlaps something."""
    if arena.xmin <= x <= arena.xmax and arena.ymin <= y <= arena.ymax:
        return
    on_track = [k for k in ("track_position", "track_distance") if reader.has(k)]
    key = on_track[0] if on_track else ("x" if not arena.xmin <= x <= arena.xmax else "y")
    reader.fail(
        key,
        "",
        message=f"robot {name!r} starts at ({x:.3g}, {y:.3g}) m, outside the arena "
        f"(x from {arena.xmin:g} to {arena.xmax:g} m, y from {arena.ymin:g} to "
        f"{arena.ymax:g} m); give a start inside the walls",
    )


def _robot_heading(reader: TableReader, track_heading: float) -> float:
    """``theta`` (or ``theta_deg``), or ``direction`` along or against the track."""
    if not reader.has("direction"):
        return reader.angle("theta", required=True)
    if not (reader.has("track_position") or reader.has("track_distance")):
        reader.fail("direction", "", message="direction needs track_position or track_distance")
    direction = reader.string("direction", choices=("along", "against"))
    if reader.has("theta") or reader.has("theta_deg"):
        reader.fail("direction", "", message="give either direction or theta, not both")
    return track_heading + (math.pi if direction == "against" else 0.0)


def read_obstacle(
    reader: TableReader, index: int, frame: TrackFrame | None
) -> CircleObstacle | PolygonObstacle:
    """One ``[[obstacles]]`` table: a circle, a box (placed like a robot) or a polygon."""
    shape = reader.string("shape", "circle", choices=OBSTACLE_SHAPES)
    name = reader.string("name", f"obstacle{index + 1}")
    colour = reader.colour("colour", (200, 60, 40))
    reflectance = reader.number(
        "ir_reflectance", 1.0, unit="share of the IR the response curve's surface sends back",
        low=0, high=1,
    )  # fmt: skip
    if shape == "polygon":
        return _polygon(reader, name, colour, reflectance)
    x, y, track_heading = place(reader, frame, "obstacle")
    if shape == "circle":
        radius = reader.number(
            "radius", unit="m", low=0.001, high=10.0, low_open=True, required=True
        )
        reader.finish()
        return CircleObstacle(x, y, radius, colour=colour, name=name, ir_reflectance=reflectance)
    if not reader.has("size"):
        reader.fail("size", "", message="missing; expected [length, width] (m)")
    length, width = reader.pair("size", positive=True)
    angle = reader.angle("angle", track_heading)
    reader.finish()
    c, s = math.cos(angle), math.sin(angle)
    corners = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * [length / 2, width / 2]
    vertices = corners @ np.array([[c, s], [-s, c]]) + [x, y]
    return PolygonObstacle(vertices, colour=colour, name=name, ir_reflectance=reflectance)


def _polygon(
    reader: TableReader, name: str, colour: tuple[int, int, int], reflectance: float
) -> PolygonObstacle:
    """A convex polygon by its vertices, turned counter-clockwise if given clockwise."""
    if not reader.has("vertices"):
        reader.fail("vertices", "", message="missing; expected at least 3 [x, y] points (m)")
    vertices = reader.points("vertices", 3)
    reader.finish()
    if _signed_area(vertices) < 0:
        vertices = vertices[::-1]
    if not _is_convex(vertices):
        reader.fail("vertices", "", message="the polygon must be convex")
    return PolygonObstacle(vertices, colour=colour, name=name, ir_reflectance=reflectance)


def read_dummy(reader: TableReader, index: int, frame: TrackFrame | None) -> Dummy:
    """One ``[[dummies]]`` table: a named point (its name becomes a CoppeliaSim object path)."""
    name = reader.string("name", f"Dummy{index}" if index else "Dummy")
    if not name or not all(c.isalnum() or c in "_-" for c in name):
        reader.fail(
            "name", "a name of letters, digits, '_' and '-' (it becomes an object path)", name
        )
    x, y, _ = place(reader, frame, "dummy")
    z = reader.number("z", 0.0, unit="m above the floor", low=-10.0, high=10.0)
    reader.finish()
    return Dummy(name, x, y, z)


def _signed_area(v: np.ndarray) -> float:
    x, y = v[:, 0], v[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _is_convex(v: np.ndarray) -> bool:
    d = np.roll(v, -1, axis=0) - v
    cross = d[:, 0] * np.roll(d, -1, axis=0)[:, 1] - d[:, 1] * np.roll(d, -1, axis=0)[:, 0]
    return bool(np.all(cross >= -1e-12))
