"""The objects of a served scene: handles, V-REP names and CoppeliaSim alias paths.

Each robot of the scene is served as a copy of the stock V-REP e-puck model. Robot 0
is ``ePuck``, the copies are ``ePuck#0``, ``ePuck#1`` ..., exactly as V-REP names copies
of a model. Every robot has these objects:

==========================  =================  ==================================
deprecated name (V-REP)     alias (4.3+)       what it is
==========================  =================  ==================================
``ePuck``                   ``ePuck``          the model base (the robot's pose)
``ePuck_leftJoint``         ``leftJoint``      left wheel joint
``ePuck_rightJoint``        ``rightJoint``     right wheel joint
``ePuck_proxSensor1..8``    ``proxSensor``     IR sensors, V-REP order (1 = left)
``ePuck_lightSensor``       ``lightSensor``    ground sensors (a 3×1 vision sensor)
``ePuck_camera``            ``camera``         the camera (a vision sensor)
==========================  =================  ==================================

with the copy's suffix on every deprecated name (``ePuck_leftJoint#0``). The proximity
sensors keep V-REP's numbering, which is *not* the real robot's: ``ePuck_proxSensor1`` is
the left side sensor (ps5), see :data:`~puckboard.records.VREP_ORDER`.

Paths follow CoppeliaSim's rules for the cases an e-puck controller needs: ``/ePuck``
(the first e-puck), ``/ePuck[1]`` (the second sibling called ePuck),
``/ePuck[1]/leftJoint``, ``/ePuck/proxSensor[3]`` (its fourth IR sensor),
``/ePuck{1}`` (the second match anywhere in the scene), ``*`` wildcards in an alias, and
a path whose alias is unique may skip levels. Names without a leading ``/`` are the
deprecated V-REP names. Relative paths (``./x``, ``:x``) need a script to be relative
to, which a remote client does not have, so they are refused with a hint.
"""

from __future__ import annotations

import fnmatch
import re
from collections.abc import Sequence
from dataclasses import dataclass

from ..profile import RobotProfile
from ..records import VREP_ORDER

__all__ = ["MODEL_NAME", "ObjectNotFound", "SceneObjects", "ServedObject", "served_model_name"]

#: The stock model's base name.
MODEL_NAME = "ePuck"

#: Object kinds, named after CoppeliaSim's object types.
MODEL = "model"
JOINT = "joint"
PROXIMITY_SENSOR = "proximity_sensor"
VISION_SENSOR = "vision_sensor"

_SEGMENT = re.compile(r"^(?P<alias>[^\[\]{}]+)(?:\[(?P<sibling>\d+)\]|\{(?P<scene>\d+)\})?$")


class ObjectNotFound(LookupError):
    """No served object matches a name or path; the message lists what exists."""


@dataclass(frozen=True)
class ServedObject:
    """One served object.

    ``part`` says what it is on the robot (``base``, ``left_joint``, ``right_joint``,
    ``prox``, ``light``, ``camera``); ``index`` is the joint side (0 left, 1 right) or the
    IR sensor's V-REP index (0 for ePuck_proxSensor1). ``offset`` is its pose on the
    robot (x forward, y left, z up in m; yaw in rad).
    """

    handle: int
    kind: str
    robot: int
    part: str
    index: int
    name: str
    alias: str
    parent: int | None
    offset: tuple[float, float, float, float]


def served_model_name(i: int, model: str = MODEL_NAME) -> str:
    """The deprecated name of robot ``i``'s model base: ``ePuck``, ``ePuck#0``, ``ePuck#1``..."""
    return model if i == 0 else f"{model}#{i - 1}"


class SceneObjects:
    """The served objects of ``len(profiles)`` e-pucks; see the module docstring."""

    def __init__(
        self,
        profiles: Sequence[RobotProfile],
        *,
        labels: Sequence[str] | None = None,
        model: str = MODEL_NAME,
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
        for i, profile in enumerate(profiles):
            self._add_robot(i, profile)
        #: Child script handles (one per robot, for ``sim.getScript``); distinct from objects.
        first_script = len(self._objects) + 1000
        self.scripts: dict[int, int] = {first_script + i: i for i in range(len(profiles))}

    # -- construction ----------------------------------------------------------------------
    def _add(self, **fields: object) -> ServedObject:
        obj = ServedObject(handle=len(self._objects) + 1, **fields)  # type: ignore[arg-type]
        self._objects.append(obj)
        self._by_handle[obj.handle] = obj
        self._by_name[obj.name] = obj
        self._children.setdefault(obj.parent, []).append(obj)
        self._children.setdefault(obj.handle, [])
        return obj

    def _add_robot(self, i: int, p: RobotProfile) -> None:
        suffix = "" if i == 0 else f"#{i - 1}"
        m = self.model
        base = self._add(
            kind=MODEL, robot=i, part="base", index=0, name=m + suffix, alias=m,
            parent=None, offset=(0.0, 0.0, 0.0, 0.0),
        )  # fmt: skip
        self.bases.append(base)
        half = p.axle_length / 2.0
        left = self._add(
            kind=JOINT, robot=i, part="left_joint", index=0, name=f"{m}_leftJoint{suffix}",
            alias="leftJoint", parent=base.handle, offset=(0.0, half, p.wheel_radius, 0.0),
        )  # fmt: skip
        right = self._add(
            kind=JOINT, robot=i, part="right_joint", index=1, name=f"{m}_rightJoint{suffix}",
            alias="rightJoint", parent=base.handle, offset=(0.0, -half, p.wheel_radius, 0.0),
        )  # fmt: skip
        self.joints.append((left, right))
        for k, ps in enumerate(VREP_ORDER):
            pose = p.prox_poses[ps]
            self._add(
                kind=PROXIMITY_SENSOR, robot=i, part="prox", index=k,
                name=f"{m}_proxSensor{k + 1}{suffix}", alias="proxSensor", parent=base.handle,
                offset=(pose.x, pose.y, 0.034, pose.heading),
            )  # fmt: skip
        centre = p.ground_poses[1]
        self._add(
            kind=VISION_SENSOR, robot=i, part="light", index=0, name=f"{m}_lightSensor{suffix}",
            alias="lightSensor", parent=base.handle, offset=(centre.x, centre.y, 0.005, 0.0),
        )  # fmt: skip
        self._add(
            kind=VISION_SENSOR, robot=i, part="camera", index=0, name=f"{m}_camera{suffix}",
            alias="camera", parent=base.handle, offset=(p.body_radius, 0.0, p.camera_height, 0.0),
        )  # fmt: skip

    # -- lookup ----------------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self._objects)

    def __iter__(self):  # type: ignore[no-untyped-def]
        return iter(self._objects)

    def get(self, handle: int) -> ServedObject | None:
        return self._by_handle.get(handle)

    def robot_objects(self, robot: int) -> list[ServedObject]:
        return [o for o in self._objects if o.robot == robot]

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
        return (
            f"object does not exist: {path!r}{which}. This server serves "
            f"{len(self.bases)} e-puck(s): {self.summary()}"
        )

    def summary(self) -> str:
        """One line naming every served robot: model name and alias path."""
        parts = []
        for i, base in enumerate(self.bases):
            parts.append(f"{base.name} = /{self.model}[{i}] (robot {self.labels[i]!r})")
        return "; ".join(parts)

    def alias_path(self, obj: ServedObject) -> str:
        """A path that names ``obj`` uniquely (``/ePuck[1]/proxSensor[2]``)."""
        base = self.bases[obj.robot]
        head = f"/{self.model}[{obj.robot}]"
        if obj is base:
            return head
        siblings = [o for o in self._children[base.handle] if o.alias == obj.alias]
        if len(siblings) > 1:
            return f"{head}/{obj.alias}[{siblings.index(obj)}]"
        return f"{head}/{obj.alias}"


def _handle(obj: ServedObject | None) -> int | None:
    return None if obj is None else obj.handle


def _alias_match(obj: ServedObject, pattern: str) -> bool:
    if "*" in pattern or "?" in pattern:
        return fnmatch.fnmatchcase(obj.alias, pattern)
    return obj.alias == pattern
