"""The object tree of a served scene: handles, V-REP names, CoppeliaSim alias paths, frames.

Each robot of the scene is served as a copy of the stock V-REP e-puck model. Robot 0
is ``ePuck``, the copies are ``ePuck#0``, ``ePuck#1`` ..., exactly as V-REP names copies
of a model. Every robot is this tree (names from the stock model's script and
third-party clients, aliases from CoppeliaSim 4.3+ scripts; see docs/coppeliasim.md for
the sources and what is inferred):

==============================  =========================  =================  ==========
deprecated name (V-REP)         alias path (4.3+)          object type        what it is
==============================  =========================  =================  ==========
``ePuck``                       ``/ePuck``                 shape, model base  the robot
``ePuck_base``                  ``/ePuck/base``            shape              its body
``ePuck_bodyElements``          ``/ePuck/bodyElements``    shape              body parts
``ePuck_ledLight``              ``/ePuck/ledLight``        light              LED light
``ePuck_leftJoint``             ``/ePuck/leftJoint``       joint              left motor
``ePuck_leftWheel``             ``…/leftRespondableWheel`` shape              left wheel
``ePuck_rightJoint``            ``/ePuck/rightJoint``      joint              right motor
``ePuck_rightWheel``            ``…/rightRespondableWheel`` shape             right wheel
``ePuck_proxSensor1..8``        ``/ePuck/proxSensor[0..7]`` proximity sensor  IR sensors
``ePuck_lightSensor``           ``/ePuck/lightSensor``     vision sensor      ground
``ePuck_camera``                ``/ePuck/camera``          vision sensor      camera
==============================  =========================  =================  ==========

with the copy's suffix on every deprecated name (``ePuck_leftJoint#0``). The proximity
sensors keep V-REP's numbering, which is *not* the real robot's: ``ePuck_proxSensor1`` is
the left side sensor (ps5), see :data:`~puckboard.records.VREP_ORDER`.

The scene's other things are served too, at the root of the tree: ``Floor`` (and the
line, ``/Floor/Track``), every obstacle under its scene name (a shape), the arena's four
walls (``Wall``, ``Wall0``, ``Wall1``, ``Wall2``; alias ``Wall``), and the scene's
dummies (``[[dummies]]`` in the scene file) under their names.

Frames follow the stock model: the base's origin is the middle of the wheel axle, x
forward, z up; a wheel joint's z axis is the wheel's axle (pointing left, so a positive
velocity drives forward); a proximity sensor's z axis is the direction it looks and its
y axis is up; the light sensor looks down; the camera looks forward.

Paths follow CoppeliaSim's rules for the cases a controller needs: ``/ePuck`` (the first
e-puck), ``/ePuck[1]`` (the second sibling called ePuck), ``/ePuck[1]/leftJoint``,
``/ePuck/proxSensor[3]`` (its fourth IR sensor), ``/ePuck{1}`` (the second match anywhere
in the scene), ``*`` wildcards in an alias, and a path whose alias is unique may skip
levels (``/ePuck/leftRespondableWheel``). Names without a leading ``/`` are the
deprecated V-REP names. Relative paths (``./x``, ``:x``) need a script to be relative
to, which a remote client does not have, so they are refused with a hint.
"""

from __future__ import annotations

import fnmatch
import math
import re
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ....profile import RobotProfile
from ....records import VREP_ORDER
from .frames import IDENTITY, Frame, frame_from_axes

if TYPE_CHECKING:
    from ....scenario.scene import Scene

__all__ = [
    "MODEL_NAME",
    "ObjectNotFound",
    "SceneObjects",
    "ServedObject",
]

#: The stock model's base name.
MODEL_NAME = "ePuck"

#: Object types, named and numbered as CoppeliaSim's ``sim.object_*_type`` constants.
SHAPE = "shape"
JOINT = "joint"
DUMMY = "dummy"
PROXIMITY_SENSOR = "proximity_sensor"
VISION_SENSOR = "vision_sensor"
LIGHT = "light"
OBJECT_TYPES: dict[str, int] = {
    SHAPE: 0, JOINT: 1, DUMMY: 4, PROXIMITY_SENSOR: 5, VISION_SENSOR: 9, LIGHT: 13,
}  # fmt: skip

#: Heights above the floor (m), from the decoded V-REP model (vrep-epuck-model reference):
#: the wheel axle (the base's origin) is at the wheel's radius, the IR sensors at 33.2 mm,
#: the light sensor 1.7 mm above the floor looking down.
PROX_HEIGHT = 0.0332
LIGHT_SENSOR_HEIGHT = 0.0017
#: Height (m) of the served obstacles and walls: the embedded world is planar and scenes
#: give none, so they are CoppeliaSim's default primitive size, tall enough for any sensor.
SCENE_OBJECT_HEIGHT = 0.1

_SEGMENT = re.compile(r"^(?P<alias>[^\[\]{}]+)(?:\[(?P<sibling>\d+)\]|\{(?P<scene>\d+)\})?$")

# A wheel joint's frame: z along the axle (robot +y, so positive turns drive forward).
_JOINT_AXES = ((1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (0.0, 1.0, 0.0))


class ObjectNotFound(LookupError):
    """No served object matches a name or path; the message lists what exists."""


@dataclass(frozen=True, eq=False)
class ServedObject:
    """One served object.

    ``kind`` is its CoppeliaSim object type (:data:`OBJECT_TYPES`). ``robot`` is the robot
    it belongs to (``None`` for the scene's own objects); ``part`` says what it is
    (``base``, ``left_joint``, ``left_wheel``, ``prox``, ``light``, ``camera`` ... on a
    robot; ``floor``, ``track``, ``obstacle``, ``wall``, ``dummy`` in the scene) and
    ``index`` which one (joint side 0 left / 1 right, the IR sensor's V-REP index, the
    obstacle's or wall's index in the scene). ``local`` is its frame in its parent's
    frame (for a robot's base and a dummy: the start pose; the served pose moves).
    """

    handle: int
    kind: str
    name: str
    alias: str
    parent: int | None
    local: Frame
    robot: int | None = None
    part: str = ""
    index: int = 0
    model: bool = False


class SceneObjects:
    """The served objects of ``len(profiles)`` e-pucks and, given ``scene``, of its
    floor, line, obstacles, walls and dummies; see the module docstring."""

    def __init__(
        self,
        profiles: Sequence[RobotProfile],
        *,
        labels: Sequence[str] | None = None,
        model: str = MODEL_NAME,
        scene: Scene | None = None,
    ) -> None:
        self.model = model
        self.labels = (
            tuple(labels) if labels is not None else tuple(str(i) for i in range(len(profiles)))
        )
        self._objects: list[ServedObject] = []
        self._by_handle: dict[int, ServedObject] = {}
        self._by_name: dict[str, ServedObject] = {}
        self._children: dict[int | None, list[ServedObject]] = {None: []}
        self.bases: list[ServedObject] = []
        self.joints: list[tuple[ServedObject, ServedObject]] = []
        #: what a proximity sensor can see: ("robot"|"obstacle"|"wall", index) -> object
        self.detectable: dict[tuple[str, int], ServedObject] = {}
        for i, profile in enumerate(profiles):
            self._add_robot(i, profile)
        if scene is not None:
            self._add_scene(scene)
        #: Child script handles (one per robot, for ``sim.getScript``); distinct from objects.
        first_script = len(self._objects) + 1000
        self.scripts: dict[int, int] = {first_script + i: i for i in range(len(profiles))}

    # -- construction ----------------------------------------------------------------------
    def _add(
        self,
        kind: str,
        name: str,
        alias: str,
        parent: ServedObject | None,
        local: Frame = IDENTITY,
        **fields: object,
    ) -> ServedObject:  # fmt: skip
        if name in self._by_name:  # V-REP makes names unique: "Cylinder", "Cylinder0" ...
            stem, n = name, 0
            while f"{stem}{n}" in self._by_name:
                n += 1
            name = f"{stem}{n}"
        obj = ServedObject(
            handle=len(self._objects) + 1, kind=kind, name=name, alias=alias,
            parent=None if parent is None else parent.handle, local=local,
            **fields,  # type: ignore[arg-type]
        )  # fmt: skip
        self._objects.append(obj)
        self._by_handle[obj.handle] = obj
        self._by_name[obj.name] = obj
        self._children.setdefault(obj.parent, []).append(obj)
        self._children.setdefault(obj.handle, [])
        return obj

    def _add_robot(self, i: int, p: RobotProfile) -> None:
        suffix = "" if i == 0 else f"#{i - 1}"
        m = self.model
        axle_z = p.wheel_radius  # the base's origin: the middle of the wheel axle

        def part(kind: str, name: str, alias: str, parent: ServedObject, local: Frame = IDENTITY,
                 **fields: object) -> ServedObject:  # fmt: skip
            return self._add(kind, f"{m}_{name}{suffix}", alias, parent, local, robot=i, **fields)

        base = self._add(SHAPE, m + suffix, m, None, IDENTITY, robot=i, part="base", model=True)
        self.bases.append(base)
        self.detectable[("robot", i)] = base
        part(SHAPE, "base", "base", base, part="body")
        part(SHAPE, "bodyElements", "bodyElements", base, part="body_elements")
        part(LIGHT, "ledLight", "ledLight", base, part="led")
        half = p.axle_length / 2.0
        joints = []
        for side, (word, y) in enumerate((("left", half), ("right", -half))):
            joint = part(
                JOINT, f"{word}Joint", f"{word}Joint", base,
                frame_from_axes(*_JOINT_AXES, position=(0.0, y, 0.0)),
                part=f"{word}_joint", index=side,
            )  # fmt: skip
            part(
                SHAPE, f"{word}Wheel", f"{word}RespondableWheel", joint,
                part=f"{word}_wheel", index=side,
            )  # fmt: skip
            joints.append(joint)
        self.joints.append((joints[0], joints[1]))
        for k, ps in enumerate(VREP_ORDER):
            pose = p.prox_poses[ps]
            c, s = math.cos(pose.heading), math.sin(pose.heading)
            frame = frame_from_axes(
                (-s, c, 0.0),
                (0.0, 0.0, 1.0),
                (c, s, 0.0),
                position=(pose.x, pose.y, PROX_HEIGHT - axle_z),
            )  # z looks where the sensor looks, y up
            part(PROXIMITY_SENSOR, f"proxSensor{k + 1}", "proxSensor", base, frame,
                 part="prox", index=k)  # fmt: skip
        ground_x = p.ground_poses[1].x
        part(
            VISION_SENSOR, "lightSensor", "lightSensor", base,
            frame_from_axes((1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0),
                            position=(ground_x, 0.0, LIGHT_SENSOR_HEIGHT - axle_z)),
            part="light",
        )  # fmt: skip
        part(
            VISION_SENSOR, "camera", "camera", base,
            frame_from_axes((0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (1.0, 0.0, 0.0),
                            position=(p.camera_forward, 0.0, p.camera_height - axle_z)),
            part="camera",
        )  # fmt: skip

    def _add_scene(self, scene: Scene) -> None:
        from ....scenario.scene import CircleObstacle

        floor = self._add(SHAPE, "Floor", "Floor", None, part="floor")
        if scene.track is not None:
            self._add(SHAPE, "Track", "Track", floor, part="track")
        half = SCENE_OBJECT_HEIGHT / 2.0
        for k, ob in enumerate(scene.obstacles):
            if isinstance(ob, CircleObstacle):
                x, y, heading = ob.x, ob.y, 0.0
            else:
                x, y = (float(v) for v in np.mean(ob.vertices, axis=0))
                edge = ob.vertices[1] - ob.vertices[0]
                heading = math.atan2(float(edge[1]), float(edge[0]))
            name = ob.name or "Obstacle"
            obj = self._add(
                SHAPE, name, name, None, Frame.planar(x, y, heading, half), part="obstacle",
                index=k,
            )  # fmt: skip
            self.detectable[("obstacle", k)] = obj
        if scene.arena is not None:
            starts, vectors = scene.arena.edges()
            for k, (a, v) in enumerate(zip(starts, vectors)):
                centre = a + v / 2.0
                frame = Frame.planar(
                    float(centre[0]), float(centre[1]), math.atan2(float(v[1]), float(v[0])), half
                )
                self.detectable[("wall", k)] = self._add(
                    SHAPE, "Wall", "Wall", None, frame, part="wall", index=k
                )
        for k, dummy in enumerate(scene.dummies):
            self._add(
                DUMMY, dummy.name, dummy.name, None, Frame.planar(dummy.x, dummy.y, 0.0, dummy.z),
                part="dummy", index=k,
            )  # fmt: skip

    # -- lookup ----------------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self._objects)

    def __iter__(self) -> Iterator[ServedObject]:
        return iter(self._objects)

    def get(self, handle: int) -> ServedObject | None:
        return self._by_handle.get(handle)

    def children(self, obj: ServedObject | None) -> list[ServedObject]:
        """Direct children of ``obj`` (``None``: the scene's root objects), in scene order."""
        return list(self._children.get(_handle(obj), []))

    def tree(self, root: ServedObject | None) -> list[ServedObject]:
        """``root`` and everything under it, depth first (``None``: the whole scene)."""
        return ([] if root is None else [root]) + self._descendants(root)

    def resolve(self, path: str, index: int = 0) -> ServedObject:
        """The object named ``path`` (deprecated name or alias path); ``index`` picks the
        n-th match, like ``sim.getObject(path, {index=n})``."""
        matches = self.find(path)
        if index < 0 or index >= len(matches):
            raise ObjectNotFound(self._not_found(path, index if matches else None))
        return matches[index]

    def find(self, path: str) -> list[ServedObject]:
        """Every object matching ``path``, in scene order."""
        if path.startswith("/"):
            return self._find_path(path)
        if path.startswith((".", ":")):
            raise ObjectNotFound(
                f"relative path {path!r} needs a script object to be relative to, and a "
                f"remote client has none; use an absolute path such as '/{self.model}/leftJoint'"
            )
        obj = self._by_name.get(path)
        return [obj] if obj is not None else []

    def _find_path(self, path: str) -> list[ServedObject]:
        segments = [s for s in path.split("/") if s]
        if not segments:
            return []
        current: list[ServedObject | None] = [None]
        for seg in segments:
            m = _SEGMENT.match(seg)
            if m is None:
                return []
            alias = m["alias"]
            matched: list[ServedObject] = []
            for parent in current:
                kids = [
                    o for o in self._children.get(_handle(parent), []) if _alias_match(o, alias)
                ]
                if not kids:  # a unique alias may skip levels
                    kids = [o for o in self._descendants(parent) if _alias_match(o, alias)]
                if m["sibling"] is not None:
                    n = int(m["sibling"])
                    kids = kids[n : n + 1]
                matched.extend(kids)
            if m["scene"] is not None:
                n = int(m["scene"])
                everywhere = [
                    o for p in current for o in self._descendants(p) if _alias_match(o, alias)
                ]
                matched = everywhere[n : n + 1]
            current = list(dict.fromkeys(matched))  # keep order, drop duplicates
            if not current:
                return []
        return [o for o in current if o is not None]

    def _descendants(self, parent: ServedObject | None) -> list[ServedObject]:
        out: list[ServedObject] = []
        stack = list(reversed(self._children.get(_handle(parent), [])))
        while stack:
            obj = stack.pop()
            out.append(obj)
            stack.extend(reversed(self._children.get(obj.handle, [])))
        return out

    def _not_found(self, path: str, index: int | None) -> str:
        which = f" (index {index})" if index is not None else ""
        others = [o.name for o in self._children[None] if o.robot is None]
        scene = f"; and in the scene: {', '.join(others)}" if others else ""
        return (
            f"object does not exist, or alias/path is ill formatted: {path!r}{which}. "
            f"This server serves "
            f"{len(self.bases)} e-puck(s): {self.summary()}{scene}"
        )

    def summary(self) -> str:
        """One line naming every served robot: model name and alias path."""
        parts = []
        for i, base in enumerate(self.bases):
            parts.append(f"{base.name} = /{self.model}[{i}] (robot {self.labels[i]!r})")
        return "; ".join(parts)

    # -- names -----------------------------------------------------------------------------
    def alias_with_order(self, obj: ServedObject) -> str:
        """``alias`` or, when siblings share it, ``alias[n]`` (its order among them)."""
        siblings = [o for o in self._children[obj.parent] if o.alias == obj.alias]
        return f"{obj.alias}[{siblings.index(obj)}]" if len(siblings) > 1 else obj.alias

    def full_path(self, obj: ServedObject) -> str:
        """The path through every ancestor: ``/ePuck[1]/leftJoint/leftRespondableWheel``."""
        parts = []
        node: ServedObject | None = obj
        while node is not None:
            parts.append(self.alias_with_order(node))
            node = self.get(node.parent) if node.parent is not None else None
        return "/" + "/".join(reversed(parts))

    def alias_path(self, obj: ServedObject) -> str:
        """A short path that names ``obj`` uniquely: from its model base, skipping levels
        whose alias is unique in the model (``/ePuck[1]/proxSensor[2]``)."""
        if obj.robot is None or obj.model:
            return self.full_path(obj)
        base = self.bases[obj.robot]
        same = [o for o in self._descendants(base) if o.alias == obj.alias]
        tail = f"{obj.alias}[{same.index(obj)}]" if len(same) > 1 else obj.alias
        return f"{self.full_path(base)}/{tail}"

    def scene_index_path(self, obj: ServedObject, *, under_model: bool = False) -> str:
        """``/alias{n}``: ``obj`` as the n-th object with its alias in the scene (or, with
        ``under_model``, ``/ePuck{i}/alias{n}`` within its model)."""
        if under_model and obj.robot is not None and not obj.model:
            base = self.bases[obj.robot]
            same = [o for o in self._descendants(base) if o.alias == obj.alias]
            return f"{self.scene_index_path(base)}/{obj.alias}{{{same.index(obj)}}}"
        same = [o for o in self._objects if o.alias == obj.alias]
        return f"/{obj.alias}{{{same.index(obj)}}}"

    def alias_is_unique(self, obj: ServedObject) -> bool:
        return sum(1 for o in self._objects if o.alias == obj.alias) == 1


def _handle(obj: ServedObject | None) -> int | None:
    return None if obj is None else obj.handle


def _alias_match(obj: ServedObject, pattern: str) -> bool:
    if "*" in pattern or "?" in pattern:
        return fnmatch.fnmatchcase(obj.alias, pattern)
    return obj.alias == pattern
