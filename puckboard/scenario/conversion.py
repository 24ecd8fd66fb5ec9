"""A scene's dict form, both ways: validated into a :class:`~.scene.Scene`, and written back.

The dict is what TOML or JSON gives (:mod:`.scenefile` reads the text); recordings store
it too, so a recorded run can be loaded again. Reading checks everything a student can
get wrong, table by table through :class:`~.reader.TableReader`, and refuses unknown
keys; parametric tracks (:mod:`.tracks`) and positions on the track (:mod:`.placement`)
are resolved here, so the :class:`Scene` holds only explicit SI values and radians.
:func:`scene_to_dict` writes that explicit form, which :func:`scene_from_dict` reads
back to an equal scene. The schema is documented in ``docs/scenarios.md``.
"""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Mapping
from typing import Any

from ..errors import SceneError
from .generated import GENERATE_KEYS, generated_data
from .placement import (
    DUMMY_KEYS,
    OBSTACLE_KEYS,
    ROBOT_KEYS,
    TrackFrame,
    read_dummy,
    read_obstacle,
    read_robot,
)
from .reader import TableReader, unique_names
from .robot_profiles import read_default_profile, robot_profile_data
from .scene import (
    GOAL_KINDS,
    Arena,
    CircleObstacle,
    Control,
    Goal,
    Noise,
    PolygonObstacle,
    RobotSpec,
    Scene,
    Track,
)
from .settings import CONTROL_LATENCY, CONTROL_PERIOD, SETTINGS
from .tracks import TRACK_KEYS, read_track

__all__ = ["for_seed", "realise", "scene_from_dict", "scene_to_dict"]

#: The keys each table may have; an unknown one is refused before anything is read, so a
#: typo names itself instead of the key it left missing (placement and tracks declare theirs).
TOP_KEYS = frozenset(
    ("name", "description", "dt", "duration", "floor_colour", "camera_size", "profile")
    + ("track", "arena", "obstacles", "dummies", "robots", "noise", "goal", "control")
    + ("generate",)
)
ARENA_KEYS = frozenset(("size", "centre", "xmin", "ymin", "xmax", "ymax", "colour"))
NOISE_KEYS = frozenset(("wheel_speed", "proximity", "ground", "start_jitter", "gyro", "gyro_bias"))
GOAL_KEYS = frozenset(("kind", "laps"))
CONTROL_KEYS = frozenset(("period", "latency"))


# -- dict → Scene ------------------------------------------------------------------------------
def scene_from_dict(
    data: Mapping[str, Any], *, source: str = "<scene>", default_name: str = "scene"
) -> Scene:
    """Validate a scene description (as read from TOML/JSON) and build the :class:`Scene`.

    Tables are read in file order (the track before what is placed on it), so the first
    mistake reported is the first one a reader of the file meets. A ``[generate]`` table
    makes the scene a generated one (:mod:`.generated`): seed 0's, carrying the data.
    """
    if "generate" in data:
        return _generated(data, source, default_name)
    top = TableReader(data, "", source, TOP_KEYS)
    name = top.string("name", default_name)
    description = top.string("description", "")
    dt = _setting(top, "dt", 0.05, "dt", "s")
    duration = _setting(top, "duration", 120.0, "duration", "s")
    floor = top.colour("floor_colour", (235, 235, 225))
    camera_size = _camera_size(top)
    track, frame = _track(top)
    arena = _arena(top)
    obstacles = tuple(
        read_obstacle(t, i, frame) for i, t in enumerate(top.items("obstacles", OBSTACLE_KEYS))
    )
    dummies = tuple(read_dummy(t, i, frame) for i, t in enumerate(top.items("dummies", DUMMY_KEYS)))
    unique_names([d.name for d in dummies], "dummies", source)
    robots = _robots(top, frame, arena)
    noise = _noise(top)
    goal = _goal(top, track)
    control = _control(top, dt)
    top.finish()
    return Scene(
        name=name,
        robots=robots,
        track=track,
        obstacles=obstacles,
        arena=arena,
        noise=noise,
        dt=dt,
        duration=duration,
        description=description,
        floor_colour=floor,
        camera_size=camera_size,
        goal=goal,
        dummies=dummies,
        control=control,
        source=source,
    )


def _generated(data: Mapping[str, Any], source: str, default_name: str) -> Scene:
    """A scene file with a ``[generate]`` table: checked, and realised for seed 0."""
    top = TableReader(data, "", source, TOP_KEYS)
    reader = top.sub("generate", GENERATE_KEYS)
    assert reader is not None
    reader.string("kind", choices=("pass",))
    reader.finish()
    if top.has("obstacles"):
        top.fail("obstacles", "", message="a generated scene draws its obstacles; remove them")
    try:
        template = json.dumps(dict(data))
    except (TypeError, ValueError):
        top.fail("generate", "", message="a generated scene's file must hold plain data")
    try:
        scene = realise(template, 0, source=source, default_name=default_name)
    except ValueError as exc:
        top.fail("generate", "", message=str(exc))
    return dataclasses.replace(scene, generate=template)


def _camera_size(top: TableReader) -> tuple[int, int]:
    """``camera_size = [width, height]`` in pixels; the e-puck's 52×39 by default."""
    if not top.has("camera_size"):
        return (52, 39)
    value = top.raw("camera_size")
    ok = (
        isinstance(value, list)
        and len(value) == 2
        and all(isinstance(v, int) and not isinstance(v, bool) and 1 <= v <= 2048 for v in value)
    )
    if not ok:
        top.fail("camera_size", "[width, height] in pixels (integers 1..2048)", value)
    return (value[0], value[1])


def _track(top: TableReader) -> tuple[Track | None, TrackFrame | None]:
    """The ``[track]`` and the frame that places things on it (None, None without one)."""
    reader = top.sub("track", TRACK_KEYS)
    if reader is None:
        return None, None
    track = read_track(reader)
    return track, TrackFrame(track)


def _arena(top: TableReader) -> Arena | None:
    """The walled ``[arena]``: by ``size`` (and ``centre``) or by its four bounds."""
    reader = top.sub("arena", ARENA_KEYS)
    if reader is None:
        return None
    if reader.has("size"):
        w, h = reader.pair("size", positive=True)
        cx, cy = reader.pair("centre") if reader.has("centre") else (0.0, 0.0)
        xmin, ymin, xmax, ymax = cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2
    else:
        xmin = reader.number("xmin", unit="m", required=True)
        ymin = reader.number("ymin", unit="m", required=True)
        xmax = reader.number("xmax", unit="m", required=True)
        ymax = reader.number("ymax", unit="m", required=True)
        if xmax <= xmin:
            reader.fail("xmax", f"a number > xmin ({xmin:g})", xmax)
        if ymax <= ymin:
            reader.fail("ymax", f"a number > ymin ({ymin:g})", ymax)
    colour = reader.colour("colour", (120, 120, 130))
    reader.finish()
    return Arena(xmin, ymin, xmax, ymax, colour=colour)


def _robots(
    top: TableReader, frame: TrackFrame | None, arena: Arena | None
) -> tuple[RobotSpec, ...]:
    """The ``[[robots]]``: at least one, names unique, each starting inside the arena,
    ``profile`` the scene's default."""
    if not top.has("robots"):
        top.fail("robots", "", message="missing; a scene needs at least one [[robots]] entry")
    if not top.table_list("robots"):
        top.fail("robots", "at least one robot", [])
    # the robots' profile unless a robot names its own (one scene can mix them)
    default_profile = read_default_profile(top)
    robots = tuple(
        read_robot(t, i, frame, default_profile, arena)
        for i, t in enumerate(top.items("robots", ROBOT_KEYS))
    )
    unique_names([r.name for r in robots], "robots", top.source)
    return robots


def _noise(top: TableReader) -> Noise:
    """The ``[noise]`` table; no noise at all without one."""
    reader = top.sub("noise", NOISE_KEYS)
    if reader is None:
        return Noise()
    words = {
        "wheel_speed": "relative σ",
        "proximity": "relative σ",
        "ground": "σ on the 0..1 scale",
        "start_jitter": "m and rad",
        "gyro": "rad/s σ",
        "gyro_bias": "rad/s",
    }
    noise = Noise(
        **{key: _setting(reader, key, 0.0, f"noise.{key}", unit) for key, unit in words.items()}
    )
    reader.finish()
    return noise


def _setting(reader: TableReader, key: str, default: float | None, name: str, unit: str) -> float:
    """``key`` of a scene file's table, within the bounds of setting ``name``
    (:mod:`.settings`: the same bounds as ``--set name=...``)."""
    setting = SETTINGS[name]
    return reader.number(
        key, default, unit=unit, low=setting.low, high=setting.high, low_open=setting.low_open
    )


def _goal(top: TableReader, track: Track | None) -> Goal:
    """The ``[goal]`` table; a goal judged along the line needs a track."""
    goal = Goal()
    reader = top.sub("goal", GOAL_KEYS)
    if reader is not None:
        goal = Goal(
            kind=reader.string("kind", "auto", choices=GOAL_KINDS),
            laps=reader.number("laps", 1.0, unit="laps", low=0.0, high=1e4),
        )
        reader.finish()
    if goal.kind in ("pass", "follow") and track is None:
        top.fail("goal.kind", "", message=f"goal {goal.kind!r} needs a [track]")
    return goal


def _control(top: TableReader, dt: float) -> Control:
    """The ``[control]`` table: the loop's period and latency (s), each a whole number of
    physics steps of ``dt``; one tick per step and no delay without one."""
    reader = top.sub("control", CONTROL_KEYS)
    if reader is None:
        return Control()
    period = (
        _setting(reader, "period", None, CONTROL_PERIOD.name, "s") if reader.has("period") else None
    )
    latency = _setting(reader, "latency", 0.0, CONTROL_LATENCY.name, "s")
    reader.finish()
    control = Control(period=period, latency=latency)
    try:
        control.steps(dt)
    except ValueError as exc:  # the message names control.period or control.latency
        raise SceneError(f"{top.source}: {exc}") from None
    return control


# -- Scene → dict ------------------------------------------------------------------------------
def scene_to_dict(scene: Scene) -> dict[str, Any]:
    """The explicit form of ``scene`` (points, coordinates, radians), loadable again by
    :func:`scene_from_dict`; JSON- and TOML-friendly (only lists, numbers, strings)."""
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
    if not scene.control.is_default(scene.dt):
        # written only when it changes the loop, so a default scene's dict stays as it was
        out["control"] = {"latency": scene.control.latency}
        if scene.control.period is not None:
            out["control"]["period"] = scene.control.period
    if scene.track is not None:
        out["track"] = {
            "shape": "points",
            "points": [[_num(x), _num(y)] for x, y in scene.track.points],
            "width": scene.track.width,
            "closed": scene.track.closed,
            "colour": list(scene.track.colour),
        }
        if scene.track.contrast != 1.0:  # written only when set: older files stay as they were
            out["track"]["contrast"] = scene.track.contrast
    if scene.arena is not None:
        a = scene.arena
        out["arena"] = {
            "xmin": a.xmin, "ymin": a.ymin, "xmax": a.xmax, "ymax": a.ymax,
            "colour": list(a.colour),
        }  # fmt: skip
    if scene.obstacles:
        out["obstacles"] = [_obstacle_to_dict(ob) for ob in scene.obstacles]
    if scene.dummies:
        out["dummies"] = [
            {"name": d.name, "x": _num(d.x), "y": _num(d.y), "z": _num(d.z)} for d in scene.dummies
        ]
    out["robots"] = [
        {"name": r.name, "x": _num(r.x), "y": _num(r.y), "theta": float(r.theta),
         "controller": r.controller, "colour": list(r.colour), **robot_profile_data(r)}
        for r in scene.robots
    ]  # fmt: skip
    return out


def _obstacle_to_dict(ob: CircleObstacle | PolygonObstacle) -> dict[str, Any]:
    out: dict[str, Any]
    if isinstance(ob, CircleObstacle):
        out = {"shape": "circle", "name": ob.name, "x": _num(ob.x), "y": _num(ob.y),
               "radius": ob.radius, "colour": list(ob.colour)}  # fmt: skip
    else:
        out = {"shape": "polygon", "name": ob.name,
               "vertices": [[_num(x), _num(y)] for x, y in ob.vertices],
               "colour": list(ob.colour)}  # fmt: skip
    if ob.ir_reflectance != 1.0:  # written only when set, as the track's contrast
        out["ir_reflectance"] = ob.ir_reflectance
    return out


def _num(v: float) -> float:
    """Coordinates rounded to the nanometre: sampled shapes give no longer tails in files."""
    return round(float(v), 9)


# -- generated scenes ----------------------------------------------------------------------
def realise(template: str, seed: int, *, source: str, default_name: str) -> Scene:
    """The scene of seed ``seed`` of a generated scene (:mod:`.generated`), from its file's
    data as JSON.

    The scene goes through its explicit form (:func:`scene_to_dict`) once, so it is
    exactly the scene that ``scenes show --seed`` prints and ``run`` reads back
    (coordinates rounded to the nanometre either way).
    """
    data = generated_data(json.loads(template), seed)
    drawn = scene_from_dict(data, source=source, default_name=default_name)
    explicit = json.loads(json.dumps(scene_to_dict(drawn)))
    return scene_from_dict(explicit, source=source, default_name=default_name)


def for_seed(scene: Scene, seed: int) -> Scene:
    """``scene`` as episode seed ``seed`` runs it: a generated scene's own track for the
    seed, any other scene as it is."""
    if scene.generate is None:
        return scene
    return realise(scene.generate, seed, source=scene.source, default_name=scene.name)
