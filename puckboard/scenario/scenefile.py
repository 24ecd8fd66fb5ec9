"""Scene files: TOML or JSON in, a validated :class:`~puckboard.scenario.scene.Scene` out.

A scene file is data a student edits by hand, so every mistake gets an error that names
the file, the field path and what was expected::

    my-scene.toml: robots[1].theta: expected a number (radians), got 'north'

Readability comes first: angles may be given in degrees (``theta_deg``), a track may be
a parametric shape (``stadium``, ``rounded_rectangle``, ``circle``) sampled to points
here, and robots and obstacles may be placed *on the track* by a fraction of the lap
(``track_position = 0.25``) instead of by coordinates. Everything is stored in SI units
and radians; :func:`scene_to_dict` writes the explicit form back out.

Shipped scenes live in ``puckboard/scenario/scenes/`` and are found by name
(:func:`scene_names`, :func:`load_scene`). The schema is documented in
``docs/scenarios.md``.
"""

from __future__ import annotations

import json
import math
import sys
from collections.abc import Mapping
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import SceneError
from ..profile import RobotProfile
from .robot_profiles import read_default_profile, read_robot_profiles, robot_profile_data
from .scene import (
    GOAL_KINDS,
    Arena,
    CircleObstacle,
    Dummy,
    Goal,
    Noise,
    PolygonObstacle,
    RobotSpec,
    Scene,
    Track,
)

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on 3.10 only
    import tomli as tomllib

__all__ = [
    "load_scene",
    "parse_scene_text",
    "scene_description",
    "scene_from_dict",
    "scene_names",
    "scene_path",
    "scene_to_dict",
]

SCENE_SUFFIXES = (".toml", ".json")
_ROBOT_COLOURS = ((60, 160, 60), (60, 90, 200), (220, 160, 30), (160, 60, 160))
_TRACK_SHAPES = ("points", "stadium", "rounded_rectangle", "circle")
_OBSTACLE_SHAPES = ("circle", "box", "polygon")


# -- finding and reading files -----------------------------------------------------------------
def _scenes_dir() -> Any:
    return resources.files("puckboard.scenario").joinpath("scenes")


def scene_names() -> list[str]:
    """Names of the shipped scenes, sorted."""
    names = [
        entry.name.rsplit(".", 1)[0]
        for entry in _scenes_dir().iterdir()
        if entry.name.endswith(SCENE_SUFFIXES)
    ]
    return sorted(names)


def scene_path(name: str) -> Any:
    """The shipped file behind scene ``name`` (a ``Traversable``); ``SceneError`` if none."""
    folder = _scenes_dir()
    for suffix in SCENE_SUFFIXES:
        candidate = folder.joinpath(name + suffix)
        if candidate.is_file():
            return candidate
    raise SceneError(
        f"unknown scene {name!r}; shipped scenes: {', '.join(scene_names())} "
        "(or give the path of a .toml or .json scene file)"
    )


def load_scene(name_or_path: str | Path) -> Scene:
    """Load a shipped scene by name, or a scene file by path (``.toml`` or ``.json``)."""
    text = str(name_or_path)
    looks_like_path = isinstance(name_or_path, Path) or text.endswith(SCENE_SUFFIXES)
    looks_like_path = looks_like_path or "/" in text or "\\" in text
    if not looks_like_path:
        entry = scene_path(text)
        return parse_scene_text(entry.read_text(encoding="utf-8"), source=entry.name)
    path = Path(name_or_path)
    if path.suffix.lower() not in SCENE_SUFFIXES:
        raise SceneError(f"{path}: scene files must end in .toml or .json")
    try:
        content = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise SceneError(f"cannot read scene file {str(path)!r}: {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise SceneError(f"{path}: scene files must be UTF-8 text") from None
    return parse_scene_text(content, source=str(path), default_name=path.stem)


def parse_scene_text(text: str, *, source: str, default_name: str | None = None) -> Scene:
    """Parse TOML or JSON text (chosen by ``source``'s suffix) into a validated scene."""
    if source.lower().endswith(".json"):
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise SceneError(f"{source}: not valid JSON: {exc}") from None
    else:
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise SceneError(f"{source}: not valid TOML: {exc}") from None
    if default_name is None:
        default_name = Path(source).name.rsplit(".", 1)[0]
    return scene_from_dict(data, source=source, default_name=default_name)


def scene_description(name: str) -> str:
    """The one-line description of a shipped scene (without building the world)."""
    return load_scene(name).description.strip().splitlines()[0] if name else ""


# -- validation helpers ------------------------------------------------------------------------
class _Reader:
    """Reads one table of the file, remembering its path for error messages."""

    def __init__(self, data: Any, path: str, source: str) -> None:
        self.source = source
        self.path = path
        if not isinstance(data, Mapping):
            self.fail("", "a table (key = value pairs)", data)
        self.data: Mapping[str, Any] = data
        self.used: set[str] = set()

    def where(self, key: str) -> str:
        if not key:
            return self.path or "(top level)"
        return f"{self.path}.{key}" if self.path else key

    def fail(self, key: str, expected: str, got: Any = None, *, message: str = "") -> None:
        text = message or f"expected {expected}, got {got!r}"
        raise SceneError(f"{self.source}: {self.where(key)}: {text}")

    def has(self, key: str) -> bool:
        return key in self.data

    def raw(self, key: str) -> Any:
        self.used.add(key)
        return self.data[key]

    def number(
        self,
        key: str,
        default: float | None = None,
        *,
        unit: str = "",
        low: float | None = None,
        high: float | None = None,
        low_open: bool = False,
        required: bool = False,
    ) -> float:
        if key not in self.data:
            if required or default is None:
                self.fail(key, "", message=f"missing; expected a number{_unit(unit)}")
            return float(default)  # type: ignore[arg-type]
        value = self.raw(key)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.fail(key, f"a number{_unit(unit)}", value)
        value = float(value)
        if not math.isfinite(value):
            self.fail(key, f"a finite number{_unit(unit)}", value)
        if low is not None and (value <= low if low_open else value < low):
            self.fail(key, f"a number {'>' if low_open else '>='} {low:g}{_unit(unit)}", value)
        if high is not None and value > high:
            self.fail(key, f"a number <= {high:g}{_unit(unit)}", value)
        return value

    def angle(self, key: str, default: float | None = None, *, required: bool = False) -> float:
        """``key`` in radians or ``key_deg`` in degrees (not both); stored in radians."""
        deg_key = f"{key}_deg"
        if key in self.data and deg_key in self.data:
            self.fail(key, "", message=f"give either {key} (radians) or {deg_key}, not both")
        if deg_key in self.data:
            return math.radians(self.number(deg_key, unit="degrees"))
        if key not in self.data and not required and default is not None:
            return default
        if key not in self.data:
            self.fail(key, "", message=f"missing; expected {key} (radians) or {deg_key} (degrees)")
        return self.number(key, unit="radians")

    def string(self, key: str, default: str | None = None, *, choices: tuple[str, ...] = ()) -> str:
        if key not in self.data:
            if default is None:
                self.fail(key, "", message="missing; expected a string")
            return default  # type: ignore[return-value]
        value = self.raw(key)
        if not isinstance(value, str):
            self.fail(key, "a string", value)
        if choices and value not in choices:
            self.fail(key, f"one of {', '.join(choices)}", value)
        return value  # type: ignore[no-any-return]

    def boolean(self, key: str, default: bool) -> bool:
        if key not in self.data:
            return default
        value = self.raw(key)
        if not isinstance(value, bool):
            self.fail(key, "true or false", value)
        return value  # type: ignore[no-any-return]

    def colour(self, key: str, default: tuple[int, int, int]) -> tuple[int, int, int]:
        if key not in self.data:
            return default
        value = self.raw(key)
        ok = (
            isinstance(value, list)
            and len(value) == 3
            and all(isinstance(c, int) and not isinstance(c, bool) and 0 <= c <= 255 for c in value)
        )
        if not ok:
            self.fail(key, "an [r, g, b] colour with integers 0..255", value)
        return (value[0], value[1], value[2])

    def pair(self, key: str, *, unit: str = "m", positive: bool = False) -> tuple[float, float]:
        value = self.raw(key)
        ok = (
            isinstance(value, list)
            and len(value) == 2
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
            and all(math.isfinite(v) for v in value)
        )
        if not ok:
            self.fail(key, f"a pair [a, b] of numbers ({unit})", value)
        if positive and min(value) <= 0:
            self.fail(key, f"a pair of positive numbers ({unit})", value)
        return (float(value[0]), float(value[1]))

    def points(self, key: str, minimum: int) -> np.ndarray:
        value = self.raw(key)
        if not isinstance(value, list) or len(value) < minimum:
            self.fail(key, f"a list of at least {minimum} [x, y] points (m)", value)
        out = np.empty((len(value), 2))
        for i, p in enumerate(value):
            ok = (
                isinstance(p, list)
                and len(p) == 2
                and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in p)
                and all(math.isfinite(v) for v in p)
            )
            if not ok:
                self.fail(f"{key}[{i}]", "an [x, y] pair of numbers (m)", p)
            out[i] = p
        return out

    def table_list(self, key: str) -> list[Any]:
        if key not in self.data:
            return []
        value = self.raw(key)
        if not isinstance(value, list):
            self.fail(key, "a list of tables ([[...]] in TOML)", value)
        return value  # type: ignore[no-any-return]

    def sub(self, key: str) -> _Reader | None:
        if key not in self.data:
            return None
        return _Reader(self.raw(key), self.where(key), self.source)

    def finish(self, extra_allowed: tuple[str, ...] = ()) -> None:
        """Refuse unknown keys (a typo would otherwise be silently ignored)."""
        unknown = [k for k in self.data if k not in self.used and k not in extra_allowed]
        if unknown:
            known = sorted(self.used | set(extra_allowed))
            hint = f"; known here: {', '.join(known)}" if known else ""
            self.fail(unknown[0], "", message=f"unknown key{hint}")


def _unit(unit: str) -> str:
    return f" ({unit})" if unit else ""


# -- track shapes ------------------------------------------------------------------------------
def _rounded_rectangle(width: float, height: float, r: float, spacing: float) -> np.ndarray:
    """Points of a rounded rectangle centred on the origin, counter-clockwise, starting
    at the middle of the bottom side heading +x."""
    hx, hy = width / 2.0 - r, height / 2.0 - r
    pieces: list[np.ndarray] = []

    def straight(a: tuple[float, float], b: tuple[float, float]) -> None:
        # one segment is exact for a straight; only the arcs need sampling
        if math.dist(a, b) > 1e-12:
            pieces.append(np.asarray([a], dtype=float))

    def arc(cx: float, cy: float, start: float) -> None:
        n = max(2, math.ceil(r * math.pi / 2.0 / spacing))
        phi = start + np.arange(n) / n * (math.pi / 2.0)
        pieces.append(np.stack([cx + r * np.cos(phi), cy + r * np.sin(phi)], axis=1))

    straight((0.0, -hy - r), (hx, -hy - r))
    arc(hx, -hy, -math.pi / 2.0)
    straight((hx + r, -hy), (hx + r, hy))
    arc(hx, hy, 0.0)
    straight((hx, hy + r), (-hx, hy + r))
    arc(-hx, hy, math.pi / 2.0)
    straight((-hx - r, hy), (-hx - r, -hy))
    arc(-hx, -hy, math.pi)
    straight((-hx, -hy - r), (0.0, -hy - r))
    pts = np.concatenate([p for p in pieces if len(p)])
    # drop exact duplicates where zero-length straights meet arcs
    keep = np.ones(len(pts), dtype=bool)
    keep[1:] = np.linalg.norm(np.diff(pts, axis=0), axis=1) > 1e-9
    return pts[keep]


def _track(reader: _Reader) -> Track:
    shape = reader.string("shape", "points", choices=_TRACK_SHAPES)
    width = reader.number("width", 0.015, unit="m", low=0.001, high=0.2)
    colour = reader.colour("colour", (20, 20, 20))
    if shape == "points":
        if not reader.has("points"):
            reader.fail("points", "", message="missing; expected a list of [x, y] points (m)")
        pts = reader.points("points", 2)
        closed = reader.boolean("closed", True)
        reader.finish()
        return Track(pts, width=width, closed=closed, colour=colour)
    spacing = reader.number("spacing", 0.01, unit="m", low=0.0005, high=0.1)
    cx, cy = reader.pair("centre") if reader.has("centre") else (0.0, 0.0)
    heading = reader.angle("heading", 0.0)
    if shape == "stadium":
        length = reader.number("length", unit="m", low=0.0, high=100.0, required=True)
        radius = reader.number("radius", unit="m", low=0.01, high=100.0, required=True)
        pts = _rounded_rectangle(length + 2 * radius, 2 * radius, radius, spacing)
    elif shape == "rounded_rectangle":
        if not reader.has("size"):
            reader.fail("size", "", message="missing; expected [width, height] (m)")
        w, h = reader.pair("size", positive=True)
        r = reader.number("corner_radius", unit="m", low=0.01, required=True)
        if 2 * r > min(w, h):
            reader.fail("corner_radius", f"at most half the smaller side ({min(w, h) / 2:g} m)", r)
        pts = _rounded_rectangle(w, h, r, spacing)
    else:  # circle
        radius = reader.number("radius", unit="m", low=0.01, high=100.0, required=True)
        n = max(8, math.ceil(2 * math.pi * radius / spacing))
        phi = -math.pi / 2.0 + np.arange(n) / n * 2 * math.pi
        pts = np.stack([radius * np.cos(phi), radius * np.sin(phi)], axis=1)
    reader.finish()
    c, s = math.cos(heading), math.sin(heading)
    pts = pts @ np.array([[c, s], [-s, c]]) + np.array([cx, cy])
    return Track(pts, width=width, closed=True, colour=colour)


class _TrackFrame:
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


def _place(reader: _Reader, frame: _TrackFrame | None, what: str) -> tuple[float, float, float]:
    """(x, y, track heading) from ``x``/``y``, or on the track from ``track_position``
    (fraction of the lap) or ``track_distance`` (m from the start), plus ``offset``."""
    on_track = [k for k in ("track_position", "track_distance") if reader.has(k)]
    if on_track:
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


def _a(noun: str) -> str:
    """``noun`` with its indefinite article: "an obstacle", "a robot"."""
    return f"{'an' if noun[:1].lower() in 'aeiou' else 'a'} {noun}"


def _robot(
    reader: _Reader, index: int, frame: _TrackFrame | None, default_profile: str | RobotProfile
) -> RobotSpec:
    name = reader.string("name", f"epuck{index + 1}")
    if not name.strip():
        reader.fail("name", "a non-empty name", name)
    x, y, track_heading = _place(reader, frame, "robot")
    if reader.has("direction"):
        if not (reader.has("track_position") or reader.has("track_distance")):
            reader.fail("direction", "", message="direction needs track_position or track_distance")
        direction = reader.string("direction", choices=("along", "against"))
        if reader.has("theta") or reader.has("theta_deg"):
            reader.fail("direction", "", message="give either direction or theta, not both")
        theta = track_heading + (math.pi if direction == "against" else 0.0)
    else:
        theta = reader.angle("theta", required=True)
    theta = math.atan2(math.sin(theta), math.cos(theta))
    controller = reader.string("controller", "improved")
    if not controller.strip():
        reader.fail(
            "controller", "a controller spec such as improved, stock or module:factory", controller
        )
    profile, actual = read_robot_profiles(reader, default_profile)
    colour = reader.colour("colour", _ROBOT_COLOURS[index % len(_ROBOT_COLOURS)])
    reader.finish()
    return RobotSpec(
        name, x, y, theta, controller=controller, colour=colour, profile=profile, actual=actual
    )


def _obstacle(
    reader: _Reader, index: int, frame: _TrackFrame | None
) -> CircleObstacle | PolygonObstacle:
    shape = reader.string("shape", "circle", choices=_OBSTACLE_SHAPES)
    name = reader.string("name", f"obstacle{index + 1}")
    colour = reader.colour("colour", (200, 60, 40))
    if shape == "polygon":
        if not reader.has("vertices"):
            reader.fail("vertices", "", message="missing; expected at least 3 [x, y] points (m)")
        vertices = reader.points("vertices", 3)
        reader.finish()
        if _signed_area(vertices) < 0:
            vertices = vertices[::-1]
        if not _is_convex(vertices):
            reader.fail("vertices", "", message="the polygon must be convex")
        return PolygonObstacle(vertices, colour=colour, name=name)
    x, y, track_heading = _place(reader, frame, "obstacle")
    if shape == "circle":
        radius = reader.number(
            "radius", unit="m", low=0.001, high=10.0, low_open=True, required=True
        )
        reader.finish()
        return CircleObstacle(x, y, radius, colour=colour, name=name)
    if not reader.has("size"):
        reader.fail("size", "", message="missing; expected [length, width] (m)")
    length, width = reader.pair("size", positive=True)
    angle = reader.angle("angle", track_heading)
    reader.finish()
    c, s = math.cos(angle), math.sin(angle)
    corners = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * [length / 2, width / 2]
    vertices = corners @ np.array([[c, s], [-s, c]]) + [x, y]
    return PolygonObstacle(vertices, colour=colour, name=name)


def _dummy(reader: _Reader, index: int, frame: _TrackFrame | None) -> Dummy:
    name = reader.string("name", f"Dummy{index}" if index else "Dummy")
    if not name or not all(c.isalnum() or c in "_-" for c in name):
        reader.fail("name", "a name of letters, digits, '_' and '-' (it becomes an object path)", name)
    x, y, _ = _place(reader, frame, "dummy")
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


# -- the whole scene ---------------------------------------------------------------------------
def scene_from_dict(
    data: Mapping[str, Any], *, source: str = "<scene>", default_name: str = "scene"
) -> Scene:
    """Validate a scene description (as read from TOML/JSON) and build the :class:`Scene`."""
    top = _Reader(data, "", source)
    name = top.string("name", default_name)
    description = top.string("description", "")
    dt = top.number("dt", 0.05, unit="s", low=0.0, high=1.0, low_open=True)
    duration = top.number("duration", 120.0, unit="s", low=0.0, high=1e6, low_open=True)
    floor = top.colour("floor_colour", (235, 235, 225))
    camera_size = (52, 39)
    if top.has("camera_size"):
        value = top.raw("camera_size")
        ok = (
            isinstance(value, list)
            and len(value) == 2
            and all(
                isinstance(v, int) and not isinstance(v, bool) and 1 <= v <= 2048 for v in value
            )
        )
        if not ok:
            top.fail("camera_size", "[width, height] in pixels (integers 1..2048)", value)
        camera_size = (value[0], value[1])

    track = None
    frame = None
    track_reader = top.sub("track")
    if track_reader is not None:
        track = _track(track_reader)
        frame = _TrackFrame(track)

    arena = None
    arena_reader = top.sub("arena")
    if arena_reader is not None:
        if arena_reader.has("size"):
            w, h = arena_reader.pair("size", positive=True)
            cx, cy = arena_reader.pair("centre") if arena_reader.has("centre") else (0.0, 0.0)
            xmin, ymin, xmax, ymax = cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2
        else:
            xmin = arena_reader.number("xmin", unit="m", required=True)
            ymin = arena_reader.number("ymin", unit="m", required=True)
            xmax = arena_reader.number("xmax", unit="m", required=True)
            ymax = arena_reader.number("ymax", unit="m", required=True)
            if xmax <= xmin:
                arena_reader.fail("xmax", f"a number > xmin ({xmin:g})", xmax)
            if ymax <= ymin:
                arena_reader.fail("ymax", f"a number > ymin ({ymin:g})", ymax)
        colour = arena_reader.colour("colour", (120, 120, 130))
        arena_reader.finish()
        arena = Arena(xmin, ymin, xmax, ymax, colour=colour)

    obstacles = []
    for i, item in enumerate(top.table_list("obstacles")):
        obstacles.append(_obstacle(_Reader(item, f"obstacles[{i}]", source), i, frame))

    dummies = []
    for i, item in enumerate(top.table_list("dummies")):
        dummies.append(_dummy(_Reader(item, f"dummies[{i}]", source), i, frame))
    _unique_names([d.name for d in dummies], "dummies", source)

    if not top.has("robots"):
        top.fail("robots", "", message="missing; a scene needs at least one [[robots]] entry")
    robot_items = top.table_list("robots")
    if not robot_items:
        top.fail("robots", "at least one robot", robot_items)
    # the robots' profile unless a robot names its own (one scene can mix them)
    default_profile = read_default_profile(top)
    robots = []
    for i, item in enumerate(robot_items):
        robots.append(_robot(_Reader(item, f"robots[{i}]", source), i, frame, default_profile))
    _unique_names([r.name for r in robots], "robots", source)

    noise = Noise()
    noise_reader = top.sub("noise")
    if noise_reader is not None:
        noise = Noise(
            wheel_speed=noise_reader.number("wheel_speed", 0.0, unit="relative σ", low=0, high=1),
            proximity=noise_reader.number("proximity", 0.0, unit="relative σ", low=0, high=1),
            ground=noise_reader.number("ground", 0.0, unit="σ on the 0..1 scale", low=0, high=1),
            start_jitter=noise_reader.number(
                "start_jitter", 0.0, unit="m and rad", low=0, high=0.5
            ),
            gyro=noise_reader.number("gyro", 0.0, unit="rad/s σ", low=0, high=1),
            gyro_bias=noise_reader.number("gyro_bias", 0.0, unit="rad/s", low=-1, high=1),
        )
        noise_reader.finish()

    goal = Goal()
    goal_reader = top.sub("goal")
    if goal_reader is not None:
        goal = Goal(
            kind=goal_reader.string("kind", "auto", choices=GOAL_KINDS),
            laps=goal_reader.number("laps", 1.0, unit="laps", low=0.0, high=1e4),
        )
        goal_reader.finish()
    if goal.kind in ("pass", "follow") and track is None:
        top.fail("goal.kind", "", message=f"goal {goal.kind!r} needs a [track]")

    top.finish()
    return Scene(
        name=name,
        robots=tuple(robots),
        track=track,
        obstacles=tuple(obstacles),
        arena=arena,
        noise=noise,
        dt=dt,
        duration=duration,
        description=description,
        floor_colour=floor,
        camera_size=camera_size,
        goal=goal,
        dummies=tuple(dummies),
    )


def _unique_names(names: list[str], table: str, source: str) -> None:
    seen: set[str] = set()
    for i, name in enumerate(names):
        if name in seen:
            raise SceneError(
                f"{source}: {table}[{i}].name: {name!r} is used twice; names must be unique"
            )
        seen.add(name)


def scene_to_dict(scene: Scene) -> dict[str, Any]:
    """The explicit form of ``scene`` (points, coordinates, radians), loadable again by
    :func:`scene_from_dict`; JSON- and TOML-friendly (only lists, numbers, strings)."""

    def num(v: float) -> float:
        return round(float(v), 9)

    out: dict[str, Any] = {
        "name": scene.name,
        "description": scene.description,
        "dt": scene.dt,
        "duration": scene.duration,
        "floor_colour": list(scene.floor_colour),
        "camera_size": list(scene.camera_size),
        "goal": {"kind": scene.goal.kind, "laps": scene.goal.laps},
        "noise": {
            "wheel_speed": scene.noise.wheel_speed,
            "proximity": scene.noise.proximity,
            "ground": scene.noise.ground,
            "start_jitter": scene.noise.start_jitter,
            "gyro": scene.noise.gyro,
            "gyro_bias": scene.noise.gyro_bias,
        },
    }
    if scene.track is not None:
        out["track"] = {
            "shape": "points",
            "points": [[num(x), num(y)] for x, y in scene.track.points],
            "width": scene.track.width,
            "closed": scene.track.closed,
            "colour": list(scene.track.colour),
        }
    if scene.arena is not None:
        a = scene.arena
        out["arena"] = {
            "xmin": a.xmin, "ymin": a.ymin, "xmax": a.xmax, "ymax": a.ymax,
            "colour": list(a.colour),
        }  # fmt: skip
    obstacles: list[dict[str, Any]] = []
    for ob in scene.obstacles:
        if isinstance(ob, CircleObstacle):
            obstacles.append(
                {"shape": "circle", "name": ob.name, "x": num(ob.x), "y": num(ob.y),
                 "radius": ob.radius, "colour": list(ob.colour)}
            )  # fmt: skip
        else:
            obstacles.append(
                {"shape": "polygon", "name": ob.name,
                 "vertices": [[num(x), num(y)] for x, y in ob.vertices], "colour": list(ob.colour)}
            )  # fmt: skip
    if obstacles:
        out["obstacles"] = obstacles
    if scene.dummies:
        out["dummies"] = [
            {"name": d.name, "x": num(d.x), "y": num(d.y), "z": num(d.z)} for d in scene.dummies
        ]
    out["robots"] = [
        {"name": r.name, "x": num(r.x), "y": num(r.y), "theta": float(r.theta),
         "controller": r.controller, "colour": list(r.colour), **robot_profile_data(r)}
        for r in scene.robots
    ]  # fmt: skip
    return out
