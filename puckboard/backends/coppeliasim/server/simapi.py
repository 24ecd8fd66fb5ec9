"""The ``sim.*`` functions this server serves, over a :class:`~puckboard.sim.world.World`.

The dispatch table :attr:`SimApi.functions` is the whole surface a client can reach;
every argument is checked against the function's parameter list before anything runs
(``bad argument #2 to 'sim.setJointTargetVelocity' (velocity: number expected, got text
string)``). Nothing a client sends is ever executed or evaluated.

``zmqRemoteApi.info('sim')`` lists CoppeliaSim's *whole* ``sim`` namespace (CoppeliaSim
4.7's names and constants, :file:`coppeliasim_sim.json`), because the official client
only creates ``sim.<name>`` for listed names: a function we do not serve then reaches
the server and is answered with what it is and what is served, instead of a bare
``AttributeError`` in the client.

Return values follow the CoppeliaSim manual (``manual.coppeliarobotics.com``,
``regularApi/sim<Name>.htm``) and CoppeliaSim 4.7's sources, so that a controller written
for CoppeliaSim runs unchanged; docs/coppeliasim.md has the table of every served
function with its semantics and where the server differs. In short:

* the scene tree is the stock e-puck model per robot plus the scene's floor, line,
  obstacles, walls and dummies (:mod:`.objects`); frames are full 3-D (:mod:`.frames`);
* ``sim.readProximitySensor`` returns the detected point in the sensor's frame (z along
  the direction it looks), the handle of the object seen (:mod:`.seen`) and the surface
  normal; before the first step of a run it returns state -1, as an unhandled sensor does;
* ``ePuck_lightSensor`` is 16×2 pixels (:mod:`.vision`);
* ``sim.stopSimulation`` restores the scene's initial state and clears signals, as
  CoppeliaSim does;
* the script function ``puckboardSenseAll`` (``sim.callScriptFunction('puckboardSenseAll',
  sim.getScript(sim.scripttype_childscript, ePuck))``) returns every sensor of one robot
  in one round trip — the thesis's ``senseAllTogether`` — and ``puckboardSetWheels(left,
  right)`` sets both wheels in one (its ``setVelocitiesForRemote``).

Stepping (``sim.setStepping``/``sim.step``) needs the client table and is finished by
the server; see :mod:`.clients`.
"""

from __future__ import annotations

import difflib
import json
import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from importlib import resources
from typing import TYPE_CHECKING, Any

import numpy as np

from ....records import VREP_ORDER
from .clients import ClientState
from .frames import Frame, rotation_z
from .objects import (
    DUMMY,
    JOINT,
    OBJECT_TYPES,
    PROXIMITY_SENSOR,
    VISION_SENSOR,
    ObjectNotFound,
    SceneObjects,
    ServedObject,
)
from .seen import nearest_in_sector
from .vision import LIGHT_SENSOR_RES, aux_packet, encode_image, light_sensor_image

if TYPE_CHECKING:
    from ....scenario.scene import Scene
    from ....sim.world import World

__all__ = ["CONSTANTS", "ApiError", "SimApi", "StepPending", "coppeliasim_names"]

log = logging.getLogger(__name__)


def coppeliasim_names() -> dict[str, Any]:
    """CoppeliaSim 4.7's ``sim`` namespace: ``functions`` (names) and ``constants``."""
    text = resources.files(__package__).joinpath("coppeliasim_sim.json").read_text("utf-8")
    return json.loads(text)  # type: ignore[no-any-return]


_NAMES = coppeliasim_names()
#: CoppeliaSim's constants (its values; a client sees them as ``sim.<name>``).
CONSTANTS: dict[str, int] = dict(_NAMES["constants"])
_C = CONSTANTS
HANDLE_WORLD = _C["handle_world"]
HANDLE_PARENT = _C["handle_parent"]
HANDLE_SCENE = _C["handle_scene"]
HANDLE_ALL = _C["handle_all"]
SCRIPTTYPE_CHILD = _C["scripttype_childscript"]
SIMULATION_STOPPED = _C["simulation_stopped"]
SIMULATION_PAUSED = _C["simulation_paused"]
SIMULATION_ADVANCING_RUNNING = _C["simulation_advancing_running"]
#: The CoppeliaSim release whose API and behaviour the server follows.
PROGRAM_VERSION = 40700
PROGRAM_REVISION = 2

#: The sense-all function served as a script function of every e-puck's child script.
SENSE_ALL = "puckboardSenseAll"
#: Both wheels in one call (the thesis's ``setVelocitiesForRemote``).
SET_WHEELS = "puckboardSetWheels"
#: Version of the script functions' interface, sent in every sense-all reply as ``api``.
SCRIPT_API = 1
#: A handle's flag bits (``sim.handleflag_*``) live above this.
_HANDLE_MASK = 0x000FFFFF


class ApiError(Exception):
    """A call that cannot be served; the message goes back to the client as ``err``."""


class StepPending:
    """Returned by ``sim.step`` when the client must wait for the simulation to advance."""


STEP_PENDING = StepPending()

_REQUIRED = object()
_VREP_INDEX = np.array(VREP_ORDER)


# -- argument checks: each returns the converted value or raises TypeError(expected) ------
def _int(v: Any) -> int:
    if isinstance(v, bool) or not isinstance(v, int):
        if isinstance(v, float) and v.is_integer() and abs(v) < 2**31:
            return int(v)  # the `cbor` encoder turns some ints into floats
        raise TypeError("integer")
    if abs(v) >= 2**31:
        raise TypeError("integer (32-bit)")
    return v


def _number(v: Any) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise TypeError("number")
    f = float(v)
    if not math.isfinite(f):
        raise TypeError("finite number")
    return f


def _string(v: Any) -> str:
    if not isinstance(v, str):
        raise TypeError("string")
    if len(v) > 1000:
        raise TypeError("string of at most 1000 characters")
    return v


def _buffer(v: Any) -> str | bytes:
    if not isinstance(v, (str, bytes)):
        raise TypeError("string or buffer")
    if len(v) > 65536:
        raise TypeError("string of at most 65536 bytes")
    return v


def _boolean(v: Any) -> bool:
    if isinstance(v, bool):
        return v
    if isinstance(v, int) and v in (0, 1):
        return bool(v)
    raise TypeError("boolean")


def _anything(v: Any) -> Any:
    return v


def _options(v: Any) -> dict[str, Any]:
    if v is None:
        return {}
    if not isinstance(v, dict) or len(v) > 16:
        raise TypeError("map")
    return v


def _int_pair(v: Any) -> tuple[int, int]:
    if not isinstance(v, list) or len(v) != 2:
        raise TypeError("array of 2 integers")
    return _int(v[0]), _int(v[1])


def _vector(n: int) -> Callable[[Any], list[float]]:
    def check(v: Any) -> list[float]:
        if not isinstance(v, list) or len(v) != n:
            raise TypeError(f"array of {n} numbers")
        return [_number(x) for x in v]

    return check


@dataclass(frozen=True)
class Param:
    name: str
    check: Callable[[Any], Any]
    default: Any = _REQUIRED


Handler = Callable[..., Any]


@dataclass
class Signals:
    """CoppeliaSim's signals: three separate name spaces, shared by every client and
    cleared when the simulation stops (a client-set signal lives for one run)."""

    string: dict[str, str | bytes] = field(default_factory=dict)
    int32: dict[str, int] = field(default_factory=dict)
    float: dict[str, float] = field(default_factory=dict)

    def clear(self) -> None:
        self.string.clear()
        self.int32.clear()
        self.float.clear()


class SimApi:
    """The served functions and the state they act on (one world, its objects).

    Only the server thread calls into it, so it holds no lock. ``reset()`` rebuilds the
    world from the scene with the same seed (``sim.stopSimulation``).
    """

    def __init__(
        self,
        scene: Scene,
        *,
        seed: int = 0,
        model: str = "ePuck",
        realtime: bool = True,
        script_functions: bool = True,
    ) -> None:
        from ....sim.world import World

        self.scene = scene
        #: Whether the e-puck's script has puckboard's functions; without them the server
        #: is the stock model in CoppeliaSim, and clients must read sensor by sensor.
        self.script_functions = script_functions
        self.seed = seed
        self.realtime = realtime
        self._world_class = World
        self.world: World = World(scene, seed=seed)
        self.objects = SceneObjects(
            self.world.profiles, labels=self.world.robot_names, model=model, scene=scene
        )
        n = len(self.world.robot_names)
        self.targets = np.zeros((n, 2))
        self.running = False
        self.paused = False
        self.signals = Signals()
        #: Where the dummies are (clients may move them); restored on stop.
        self.dummy_frames: dict[int, Frame] = {}
        self._visibility: dict[int, int] = {}
        self._int_params: dict[int, int] = {_C["intparam_idle_fps"]: 8}
        self._restore_scene_state()
        self.functions: dict[str, tuple[Handler, tuple[Param, ...]]] = self._table()
        self._coppeliasim = frozenset("sim." + f for f in _NAMES["functions"])

    # -- the dispatch table ------------------------------------------------------------------
    def _table(self) -> dict[str, tuple[Handler, tuple[Param, ...]]]:
        P = Param
        handle = P("objectHandle", _int)
        rel = P("relativeToObjectHandle", _int, HANDLE_WORLD)
        img_args = (
            P("sensorHandle", _int),
            P("options", _int, 0),
            P("rgbaCutOff", _number, 0.0),
            P("pos", _int_pair, (0, 0)),
            P("size", _int_pair, (0, 0)),
        )
        return {
            # the scene tree
            "sim.getObject": (self.get_object, (P("objectPath", _string), P("options", _options, {}))),
            "sim.getObjectHandle": (self.get_object_handle, (P("objectName", _string),)),
            "sim.getObjectAlias": (self.get_object_alias, (handle, P("options", _int, -1))),
            "sim.getObjectName": (self.get_object_name, (handle,)),
            "sim.getObjectType": (self.get_object_type, (handle,)),
            "sim.getObjectParent": (self.get_object_parent, (handle,)),
            "sim.getObjectChild": (self.get_object_child, (handle, P("index", _int))),
            "sim.getObjectsInTree": (
                self.get_objects_in_tree,
                (P("treeBaseHandle", _int), P("objectType", _int, HANDLE_ALL), P("options", _int, 0)),
            ),
            "sim.getObjects": (self.get_objects, (P("index", _int), P("objectType", _int))),
            "sim.isHandle": (self.is_handle, (handle,)),
            "sim.getModelProperty": (self.get_model_property, (handle,)),
            "sim.getObjectSizeFactor": (self.get_object_size_factor, (handle,)),
            # poses
            "sim.getObjectPosition": (self.get_object_position, (handle, rel)),
            "sim.getObjectOrientation": (self.get_object_orientation, (handle, rel)),
            "sim.getObjectQuaternion": (self.get_object_quaternion, (handle, rel)),
            "sim.getObjectPose": (self.get_object_pose, (handle, rel)),
            "sim.getObjectMatrix": (self.get_object_matrix, (handle, rel)),
            "sim.getObjectVelocity": (self.get_object_velocity, (handle,)),
            "sim.setObjectPosition": (self.set_object_position, (handle, P("position", _anything), P("relativeToObjectHandle", _anything, HANDLE_WORLD))),
            "sim.setObjectPose": (self.set_object_pose, (handle, P("pose", _anything), P("relativeToObjectHandle", _anything, HANDLE_WORLD))),
            # joints
            "sim.setJointTargetVelocity": (
                self.set_joint_target_velocity,
                (P("jointHandle", _int), P("targetVelocity", _number), P("params", _anything, None)),
            ),
            "sim.getJointTargetVelocity": (self.get_joint_target_velocity, (P("jointHandle", _int),)),
            "sim.getJointPosition": (self.get_joint_position, (P("jointHandle", _int),)),
            "sim.getJointVelocity": (self.get_joint_velocity, (P("jointHandle", _int),)),
            # sensors
            "sim.readProximitySensor": (self.read_proximity_sensor, (P("sensorHandle", _int),)),
            "sim.handleProximitySensor": (self.read_proximity_sensor, (P("sensorHandle", _int),)),
            "sim.readVisionSensor": (self.read_vision_sensor, (P("sensorHandle", _int),)),
            "sim.handleVisionSensor": (self.handle_vision_sensor, (P("sensorHandle", _int),)),
            "sim.getVisionSensorRes": (self.get_vision_sensor_res, (P("sensorHandle", _int),)),
            "sim.getVisionSensorImg": (self.get_vision_sensor_img, img_args),
            "sim.getVisionSensorCharImage": (
                self.get_vision_sensor_char_image,
                (P("sensorHandle", _int), P("posX", _int, 0), P("posY", _int, 0), P("sizeX", _int, 0), P("sizeY", _int, 0), P("rgbaCutOff", _number, 0.0)),
            ),
            "sim.getVisionSensorImage": (
                self.get_vision_sensor_image,
                (P("sensorHandle", _int), P("posX", _int, 0), P("posY", _int, 0), P("sizeX", _int, 0), P("sizeY", _int, 0), P("returnType", _int, 0)),
            ),
            # parameters
            "sim.getObjectInt32Param": (self.get_object_int32_param, (handle, P("parameterID", _int))),
            "sim.setObjectInt32Param": (self.set_object_int32_param, (handle, P("parameterID", _int), P("parameter", _int))),
            "sim.getInt32Param": (self.get_int32_param, (P("parameter", _int),)),
            "sim.setInt32Param": (self.set_int32_param, (P("parameter", _int), P("intState", _int))),
            "sim.getFloatParam": (self.get_float_param, (P("parameter", _int),)),
            "sim.getBoolParam": (self.get_bool_param, (P("parameter", _int),)),
            # signals
            **_signal_functions("String", self.signals.string, _buffer),
            **_signal_functions("Int32", self.signals.int32, _int),
            **_signal_functions("Float", self.signals.float, _number),
            # the simulation
            "sim.getSimulationTime": (self.get_simulation_time, ()),
            "sim.getSimulationTimeStep": (self.get_simulation_time_step, ()),
            "sim.getSimulationState": (self.get_simulation_state, ()),
            "sim.getSystemTime": (self.get_system_time, ()),
            "sim.startSimulation": (self.start_simulation, ()),
            "sim.pauseSimulation": (self.pause_simulation, ()),
            "sim.stopSimulation": (self.stop_simulation, (P("wait", _anything, None),)),
            "sim.setStepping": (self.set_stepping, (P("enabled", _boolean),)),
            "sim.step": (self.step, (P("wait", _anything, None),)),
            "sim.addLog": (self.add_log, (P("verbosityLevel", _int), P("logMessage", _string))),
            "sim.addStatusbarMessage": (self.add_statusbar_message, (P("message", _string),)),
            # scripts
            "sim.getScript": (
                self.get_script,
                (P("scriptType", _int), P("objectHandle", _int, -1), P("scriptName", _anything, None)),
            ),
            "sim.callScriptFunction": (
                self.call_script_function,
                (P("functionName", _string), P("scriptHandle", _anything)),
            ),
        }  # fmt: skip

    def info(self) -> dict[str, Any]:
        """What ``zmqRemoteApi.info('sim')`` returns: CoppeliaSim's whole ``sim`` namespace
        (functions and constants), so that unserved functions reach the server."""
        out: dict[str, Any] = {name: {"func": {}} for name in _NAMES["functions"]}
        for name in self.functions:
            out[name.removeprefix("sim.")] = {"func": {}}
        for name, value in CONSTANTS.items():
            out[name] = {"const": value}
        return out

    def call(self, client: ClientState, func: str, args: list[Any]) -> Any:
        """Run ``func`` for ``client``: a list of return values, or :data:`STEP_PENDING`.

        Raises :class:`ApiError` for unknown functions and bad arguments.
        """
        entry = self.functions.get(func)
        if entry is None:
            raise ApiError(self._unknown(func))
        handler, params = entry
        values = self._check_args(func, params, args)
        return handler(client, *values)

    def _unknown(self, func: str) -> str:
        served = f"this server serves {len(self.functions)} sim.* functions, listed in "
        served += "docs/coppeliasim.md and by 'puckboard serve --functions'"
        if func in self._coppeliasim:
            return (
                f"{func} is part of CoppeliaSim's API but puckboard serve does not serve it "
                f"({served})"
            )
        close = difflib.get_close_matches(func, list(self.functions), n=2, cutoff=0.75)
        hint = f"; did you mean {' or '.join(close)}?" if close else ""
        return f"No such function: {func}{hint} ({served})"

    @staticmethod
    def _check_args(func: str, params: tuple[Param, ...], args: list[Any]) -> list[Any]:
        if func == "sim.callScriptFunction":
            extra = args[len(params) :]
            args = args[: len(params)]
        else:
            extra = []
            while len(args) > len(params) and args[-1] is None:
                args = args[:-1]  # argsL padding
            if len(args) > len(params):
                raise ApiError(
                    f"too many arguments to '{func}': {len(args)} given, at most {len(params)} "
                    f"({', '.join(p.name for p in params)})"
                )
        values = []
        for i, p in enumerate(params):
            v = args[i] if i < len(args) else None
            if v is None:
                if p.default is _REQUIRED:
                    raise ApiError(
                        f"bad argument #{i + 1} to '{func}' ({p.name}: missing; "
                        f"{func}({', '.join(q.name for q in params)}))"
                    )
                values.append(p.default)
                continue
            try:
                values.append(p.check(v))
            except TypeError as exc:
                raise ApiError(
                    f"bad argument #{i + 1} to '{func}' ({p.name}: {exc} expected, "
                    f"got {_type_name(v)})"
                ) from None
        return values + list(extra)

    # -- objects -----------------------------------------------------------------------------
    def _object(self, handle: int, func: str, kind: str | None = None) -> ServedObject:
        obj = self.objects.get(handle & _HANDLE_MASK if handle > 0 else handle)
        if obj is None:
            raise ApiError(f"{func}: object does not exist (handle {handle})")
        if kind is not None and obj.kind != kind:
            raise ApiError(
                f"{func}: object {obj.name} (handle {handle}) is a {obj.kind.replace('_', ' ')}, "
                f"not a {kind.replace('_', ' ')}"
            )
        return obj

    def get_object(self, client: ClientState, path: str, options: dict[str, Any]) -> list[Any]:
        index = options.get("index", 0)
        if isinstance(index, bool) or not isinstance(index, int):
            raise ApiError("sim.getObject: options.index must be an integer")
        try:
            return [self.objects.resolve(path, index).handle]
        except ObjectNotFound as exc:
            if options.get("noError") is True:
                return [-1]
            raise ApiError(f"sim.getObject: {exc}") from None

    def get_object_handle(self, client: ClientState, name: str) -> list[Any]:
        try:
            return [self.objects.resolve(name).handle]
        except ObjectNotFound as exc:
            raise ApiError(f"sim.getObjectHandle: {exc}") from None

    def get_object_alias(self, client: ClientState, handle: int, options: int) -> list[Any]:
        obj = self._object(handle, "sim.getObjectAlias")
        objs = self.objects
        if options == -1:
            return [obj.alias]
        if options == 0:
            return [objs.alias_with_order(obj)]
        if options == 1:
            return [objs.alias_path(obj)]
        if options in (2, 5):
            return [objs.full_path(obj)]
        if options == 3 and objs.alias_is_unique(obj):
            return [obj.alias]
        if options in (3, 4):
            return [f"{obj.alias}__{obj.handle}__"]
        if options in (6, 7):
            return [objs.scene_index_path(obj, under_model=options == 7)]
        raise ApiError(f"sim.getObjectAlias: options must be -1..7, got {options}")

    def get_object_name(self, client: ClientState, handle: int) -> list[Any]:
        return [self._object(handle, "sim.getObjectName").name]

    def get_object_type(self, client: ClientState, handle: int) -> list[Any]:
        return [OBJECT_TYPES[self._object(handle, "sim.getObjectType").kind]]

    def get_object_parent(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.getObjectParent")
        return [obj.parent if obj.parent is not None else -1]

    def get_object_child(self, client: ClientState, handle: int, index: int) -> list[Any]:
        obj = self._object(handle, "sim.getObjectChild")
        kids = self.objects.children(obj)
        return [kids[index].handle if 0 <= index < len(kids) else -1]

    def get_objects_in_tree(
        self, client: ClientState, base: int, object_type: int, options: int
    ) -> list[Any]:
        func = "sim.getObjectsInTree"
        root = None if base == HANDLE_SCENE else self._object(base, func)
        if options & 2:  # first children only
            found = self.objects.children(root)
        else:
            found = self.objects.tree(root)
            if options & 1 and root is not None:  # exclude the tree base
                found = found[1:]
        if object_type != HANDLE_ALL:
            found = [o for o in found if OBJECT_TYPES[o.kind] == object_type]
        return [[o.handle for o in found]]

    def get_objects(self, client: ClientState, index: int, object_type: int) -> list[Any]:
        found = [
            o for o in self.objects if object_type in (HANDLE_ALL, OBJECT_TYPES[o.kind])
        ]
        return [found[index].handle if 0 <= index < len(found) else -1]

    def is_handle(self, client: ClientState, handle: int) -> list[Any]:
        return [self.objects.get(handle) is not None]

    def get_model_property(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.getModelProperty")
        return [0 if obj.model else _C["modelproperty_not_model"]]

    def get_object_size_factor(self, client: ClientState, handle: int) -> list[Any]:
        self._object(handle, "sim.getObjectSizeFactor")
        return [1.0]  # served models are never scaled

    # -- poses -------------------------------------------------------------------------------
    def world_frame(self, obj: ServedObject) -> Frame:
        """Where ``obj`` is now, in the world."""
        if obj.model and obj.robot is not None:
            x, y, theta = self.world.poses[obj.robot].tolist()
            return Frame.planar(x, y, theta, self.world.profiles[obj.robot].wheel_radius)
        if obj.kind == DUMMY:
            return self.dummy_frames[obj.handle]
        local = obj.local
        if obj.part in ("left_wheel", "right_wheel") and obj.robot is not None:
            angle = float(self.world.encoders[obj.robot, obj.index])
            local = Frame(local.rotation @ rotation_z(angle), local.position)
        if obj.parent is None:
            return local
        parent = self.objects.get(obj.parent)
        assert parent is not None
        return self.world_frame(parent).compose(local)

    def _reference(self, obj: ServedObject, rel: int, func: str) -> Frame | None:
        """The frame a ``relativeToObjectHandle`` names for ``obj``: ``None`` for the world
        (``sim.handle_world``, or ``sim.handle_parent`` of a root object), else the parent's
        or that object's frame in the world."""
        if rel == HANDLE_WORLD or (rel == HANDLE_PARENT and obj.parent is None):
            return None
        ref = self._object(obj.parent if rel == HANDLE_PARENT else rel, func)  # type: ignore[arg-type]
        return self.world_frame(ref)

    def _frame(self, handle: int, rel: int, func: str) -> Frame:
        obj = self._object(handle, func)
        frame = self.world_frame(obj)
        ref = self._reference(obj, rel, func)
        return frame if ref is None else frame.relative_to(ref)

    def get_object_position(self, client: ClientState, handle: int, rel: int) -> list[Any]:
        return [self._frame(handle, rel, "sim.getObjectPosition").position.tolist()]

    def get_object_orientation(self, client: ClientState, handle: int, rel: int) -> list[Any]:
        return [self._frame(handle, rel, "sim.getObjectOrientation").euler()]

    def get_object_quaternion(self, client: ClientState, handle: int, rel: int) -> list[Any]:
        return [self._frame(handle, rel, "sim.getObjectQuaternion").quaternion()]

    def get_object_pose(self, client: ClientState, handle: int, rel: int) -> list[Any]:
        return [self._frame(handle, rel, "sim.getObjectPose").pose7()]

    def get_object_matrix(self, client: ClientState, handle: int, rel: int) -> list[Any]:
        return [self._frame(handle, rel, "sim.getObjectMatrix").matrix12()]

    def get_object_velocity(self, client: ClientState, handle: int) -> list[Any]:
        """Linear and angular velocity (world frame) of a rigid part of a robot; a wheel
        also spins about its axle. Static objects and dummies: zero."""
        obj = self._object(handle, "sim.getObjectVelocity")
        if obj.robot is None:
            return [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
        i = obj.robot
        profile = self.world.profiles[i]
        left, right = self.world.wheel_speeds[i].tolist()
        forward, turn = profile.body_velocity(left, right)
        theta = float(self.world.poses[i, 2])
        base = self.world_frame(self.objects.bases[i])
        offset = self.world_frame(obj).position - base.position
        linear = np.array([forward * math.cos(theta), forward * math.sin(theta), 0.0])
        linear += np.cross([0.0, 0.0, turn], offset)
        angular = np.array([0.0, 0.0, turn])
        if obj.part in ("left_wheel", "right_wheel"):
            spin = left if obj.index == 0 else right
            angular += spin * base.rotation @ np.array([0.0, 1.0, 0.0])
        return [linear.tolist(), angular.tolist()]

    def _movable(
        self, handle: int, func: str, value: Any, rel: Any
    ) -> tuple[ServedObject, Any, int]:
        if isinstance(value, (int, float)) and isinstance(rel, list):
            value, rel = rel, value  # the pre-4.5 argument order (handle, rel, value)
        obj = self._object(handle, func)
        if obj.kind != DUMMY:
            raise ApiError(
                f"{func}: {obj.name} cannot be moved: puckboard serve moves robots only "
                f"through their wheels and keeps the scene's shapes where the scene puts "
                f"them; only dummies ({', '.join(self._dummy_names()) or 'none in this scene'}) "
                f"can be placed"
            )
        if isinstance(rel, bool) or not isinstance(rel, int):
            raise ApiError(f"bad argument #3 to '{func}' (relativeToObjectHandle: integer expected)")
        return obj, value, rel

    def _dummy_names(self) -> list[str]:
        return [o.name for o in self.objects if o.kind == DUMMY]

    def set_object_position(
        self, client: ClientState, handle: int, position: Any, rel: Any
    ) -> list[Any]:
        func = "sim.setObjectPosition"
        obj, position, rel = self._movable(handle, func, position, rel)
        try:
            xyz = np.array(_vector(3)(position))
        except TypeError:
            raise ApiError(f"bad argument #2 to '{func}' (position: array of 3 numbers expected)") from None
        ref = self._reference(obj, rel, func)
        current = self.dummy_frames[obj.handle]
        self.dummy_frames[obj.handle] = Frame(current.rotation, xyz if ref is None else ref.apply(xyz))
        return []

    def set_object_pose(self, client: ClientState, handle: int, pose: Any, rel: Any) -> list[Any]:
        func = "sim.setObjectPose"
        obj, pose, rel = self._movable(handle, func, pose, rel)
        try:
            local = Frame.from_pose7(_vector(7)(pose))
        except TypeError:
            raise ApiError(f"bad argument #2 to '{func}' (pose: array of 7 numbers expected)") from None
        except ValueError as exc:
            raise ApiError(f"{func}: {exc}") from None
        ref = self._reference(obj, rel, func)
        self.dummy_frames[obj.handle] = local if ref is None else ref.compose(local)
        return []

    # -- joints ------------------------------------------------------------------------------
    def _joint(self, handle: int, func: str) -> tuple[int, int]:
        obj = self._object(handle, func, JOINT)
        assert obj.robot is not None
        return obj.robot, obj.index

    def set_joint_target_velocity(
        self, client: ClientState, handle: int, velocity: float, _params: Any
    ) -> list[Any]:
        robot, side = self._joint(handle, "sim.setJointTargetVelocity")
        self.targets[robot, side] = velocity
        left, right = self.targets[robot].tolist()
        self.world.set_wheel_speeds(robot, left, right)
        client.robots.add(robot)
        return []

    def get_joint_target_velocity(self, client: ClientState, handle: int) -> list[Any]:
        robot, side = self._joint(handle, "sim.getJointTargetVelocity")
        return [float(self.targets[robot, side])]

    def get_joint_position(self, client: ClientState, handle: int) -> list[Any]:
        robot, side = self._joint(handle, "sim.getJointPosition")
        return [math.remainder(float(self.world.encoders[robot, side]), math.tau)]

    def get_joint_velocity(self, client: ClientState, handle: int) -> list[Any]:
        robot, side = self._joint(handle, "sim.getJointVelocity")
        return [float(self.world.wheel_speeds[robot, side])]

    def stop_robot(self, robot: int) -> None:
        """Zero a robot's wheel targets (a vanished client's robot)."""
        self.targets[robot] = 0.0
        self.world.set_wheel_speeds(robot, 0.0, 0.0)

    # -- sensors -----------------------------------------------------------------------------
    @property
    def sensors_handled(self) -> bool:
        """CoppeliaSim handles sensors in each simulation step: before the first step of a
        run (or while stopped) a sensor has no result and reads state -1."""
        return self.running and self.world.step_count > 0

    def read_proximity_sensor(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.readProximitySensor", PROXIMITY_SENSOR)
        nothing = [0.0, 0.0, 0.0]
        if not self.sensors_handled:
            return [-1, 0.0, nothing, -1, nothing]
        i = obj.robot
        assert i is not None
        ps = VREP_ORDER[obj.index]
        d = float(self.world.prox_distance[i, ps])
        profile = self.world.profiles[i]
        if not d < profile.prox_range:
            return [0, 0.0, nothing, -1, nothing]
        seen = nearest_in_sector(
            self.scene, self.world.poses.tolist(), self.world.profiles, i, ps,
            reach=max(d, profile.prox_max_distance) * 1.5,
        )  # fmt: skip
        if seen is None:  # rays saw what the sector misses: straight ahead, object unknown
            return [1, d, [0.0, 0.0, d], -1, [0.0, 0.0, -1.0]]
        sensor = self.world_frame(obj)
        apex = sensor.position
        towards = np.array([seen.point[0] - apex[0], seen.point[1] - apex[1], 0.0])
        length = float(np.linalg.norm(towards))
        direction = towards / length if length > 0 else sensor.rotation[:, 2]
        point = sensor.rotation.T @ (direction * d)
        normal = sensor.rotation.T @ np.array([seen.normal[0], seen.normal[1], 0.0])
        target = self.objects.detectable.get(seen.key)
        return [1, d, point.tolist(), target.handle if target else -1, normal.tolist()]

    def _image(self, obj: ServedObject) -> np.ndarray:
        """The sensor's image, rows in sending order (bottom row first)."""
        assert obj.robot is not None
        if obj.part == "light":
            return light_sensor_image(self.world, obj.robot)
        return self.world.render_camera(obj.robot)[::-1]

    def _resolution(self, obj: ServedObject) -> tuple[int, int]:
        if obj.part == "light":
            return LIGHT_SENSOR_RES
        w, h = self.scene.camera_size
        return int(w), int(h)

    def read_vision_sensor(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.readVisionSensor", VISION_SENSOR)
        if not self.sensors_handled:
            return [-1]
        return [0, aux_packet(self._image(obj)), []]

    def handle_vision_sensor(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.handleVisionSensor", VISION_SENSOR)
        return [0, aux_packet(self._image(obj)), []]

    def get_vision_sensor_res(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.getVisionSensorRes", VISION_SENSOR)
        return [list(self._resolution(obj))]

    def _window(
        self, obj: ServedObject, func: str, pos: tuple[int, int], size: tuple[int, int]
    ) -> np.ndarray:
        w, h = self._resolution(obj)
        image = self._image(obj)
        x, y = pos
        sw, sh = size
        if sw <= 0 or sh <= 0:
            sw, sh = w, h
        if x < 0 or y < 0 or x + sw > w or y + sh > h:
            raise ApiError(
                f"{func}: window pos={[x, y]} size={[sw, sh]} lies outside the {w}×{h} image"
            )
        return image[y : y + sh, x : x + sw]

    def get_vision_sensor_img(
        self,
        client: ClientState,
        handle: int,
        options: int,
        _cutoff: float,
        pos: tuple[int, int],
        size: tuple[int, int],
    ) -> list[Any]:
        func = "sim.getVisionSensorImg"
        obj = self._object(handle, func, VISION_SENSOR)
        image = self._window(obj, func, pos, size)
        return [encode_image(image, options), list(self._resolution(obj))]

    def get_vision_sensor_char_image(
        self, client: ClientState, handle: int, x: int, y: int, sw: int, sh: int, _cutoff: float
    ) -> list[Any]:
        func = "sim.getVisionSensorCharImage"
        obj = self._object(handle, func, VISION_SENSOR)
        image = self._window(obj, func, (x, y), (sw, sh))
        w, h = self._resolution(obj)
        return [encode_image(image, 1 if _greyscale(handle) else 0), w, h]

    def get_vision_sensor_image(
        self, client: ClientState, handle: int, x: int, y: int, sw: int, sh: int, ret: int
    ) -> list[Any]:
        """The deprecated float image (0..1 per channel), as the V-REP-era scripts read it."""
        func = "sim.getVisionSensorImage"
        obj = self._object(handle, func, VISION_SENSOR)
        image = self._window(obj, func, (x, y), (sw, sh)).astype(float) / 255.0
        if _greyscale(handle):
            image = image.mean(axis=2)
        if ret == 1:
            return [np.rint(image * 255.0).astype(np.uint8).tobytes()]
        return [image.ravel().tolist()]

    # -- parameters --------------------------------------------------------------------------
    def get_object_int32_param(self, client: ClientState, handle: int, param: int) -> list[Any]:
        func = "sim.getObjectInt32Param"
        obj = self._object(handle, func)
        if param == _C["objintparam_visibility_layer"]:
            return [self._visibility.get(obj.handle, 1)]
        if obj.kind == VISION_SENSOR and param == _C["visionintparam_resolution_x"]:
            return [self._resolution(obj)[0]]
        if obj.kind == VISION_SENSOR and param == _C["visionintparam_resolution_y"]:
            return [self._resolution(obj)[1]]
        if obj.kind == JOINT and param in (
            _C["jointintparam_motor_enabled"], _C["jointintparam_ctrl_enabled"]
        ):  # fmt: skip
            return [1 if param == _C["jointintparam_motor_enabled"] else 0]
        if obj.kind == "shape" and param == _C["shapeintparam_static"]:
            return [0 if obj.robot is not None else 1]
        if obj.kind == "shape" and param == _C["shapeintparam_respondable"]:
            return [1 if obj.part in ("base", "obstacle", "wall", "floor") else 0]
        raise ApiError(
            f"{func}: parameter {param} of {obj.name} is not served; served: "
            "sim.objintparam_visibility_layer, sim.visionintparam_resolution_x/_y, "
            "sim.jointintparam_motor_enabled/_ctrl_enabled, sim.shapeintparam_static/_respondable"
        )

    def set_object_int32_param(
        self, client: ClientState, handle: int, param: int, value: int
    ) -> list[Any]:
        func = "sim.setObjectInt32Param"
        obj = self._object(handle, func)
        if param == _C["objintparam_visibility_layer"]:
            self._visibility[obj.handle] = value  # what is drawn: nothing the robots sense
            return []
        if obj.kind == JOINT and param == _C["jointintparam_motor_enabled"] and value == 1:
            return []
        raise ApiError(
            f"{func}: cannot set parameter {param} of {obj.name} to {value}: the served robots' "
            "wheels are always velocity-controlled motors and the model is fixed; settable: "
            "sim.objintparam_visibility_layer"
        )

    def get_int32_param(self, client: ClientState, param: int) -> list[Any]:
        if param == _C["intparam_program_version"]:
            return [PROGRAM_VERSION]
        if param == _C["intparam_program_revision"]:
            return [PROGRAM_REVISION]
        if param in self._int_params:
            return [self._int_params[param]]
        raise ApiError(
            f"sim.getInt32Param: parameter {param} is not served; served: "
            "sim.intparam_program_version, sim.intparam_program_revision, sim.intparam_idle_fps"
        )

    def set_int32_param(self, client: ClientState, param: int, value: int) -> list[Any]:
        if param == _C["intparam_idle_fps"]:
            self._int_params[param] = value  # the server answers at once whatever the rate
            return []
        raise ApiError(
            f"sim.setInt32Param: parameter {param} is not settable here; settable: "
            "sim.intparam_idle_fps"
        )

    def get_float_param(self, client: ClientState, param: int) -> list[Any]:
        if param == _C["floatparam_simulation_time_step"]:
            return [float(self.world.dt)]
        raise ApiError(
            f"sim.getFloatParam: parameter {param} is not served; served: "
            "sim.floatparam_simulation_time_step"
        )

    def get_bool_param(self, client: ClientState, param: int) -> list[Any]:
        if param == _C["boolparam_realtime_simulation"]:
            return [self.realtime]
        raise ApiError(
            f"sim.getBoolParam: parameter {param} is not served; served: "
            "sim.boolparam_realtime_simulation"
        )

    # -- simulation --------------------------------------------------------------------------
    def get_simulation_time(self, client: ClientState) -> list[Any]:
        return [float(self.world.time)]

    def get_simulation_time_step(self, client: ClientState) -> list[Any]:
        return [float(self.world.dt)]

    def get_simulation_state(self, client: ClientState) -> list[Any]:
        if not self.running:
            return [SIMULATION_STOPPED]
        return [SIMULATION_PAUSED if self.paused else SIMULATION_ADVANCING_RUNNING]

    def get_system_time(self, client: ClientState) -> list[Any]:
        return [time.monotonic()]

    def start_simulation(self, client: ClientState) -> list[Any]:
        if not self.running or self.paused:
            log.info(
                "simulation %s by client %s", "resumed" if self.paused else "started", client.short
            )
        if not self.running:
            self.running = True
            self.world.start()
        self.paused = False
        return [1]

    def pause_simulation(self, client: ClientState) -> list[Any]:
        if not self.running:
            return [-1]  # CoppeliaSim: nothing to pause
        if not self.paused:
            self.paused = True
            log.info("simulation paused by client %s at t=%.2f s", client.short, self.world.time)
        return [1]

    def stop_simulation(self, client: ClientState, _wait: Any = None) -> list[Any]:
        """Stop and restore the initial scene (the server releases waiting clients)."""
        if self.running:
            log.info(
                "simulation stopped by client %s at t=%.2f s; scene restored",
                client.short,
                self.world.time,
            )
        self.running = False
        self.paused = False
        self.reset()
        return [1]

    @property
    def advancing(self) -> bool:
        """Running and not paused: the simulation may step."""
        return self.running and not self.paused

    def reset(self) -> None:
        self.world = self._world_class(self.scene, seed=self.seed)
        self.targets[:] = 0.0
        self._restore_scene_state()

    def _restore_scene_state(self) -> None:
        self.signals.clear()
        self.dummy_frames = {o.handle: o.local for o in self.objects if o.kind == DUMMY}

    def set_stepping(self, client: ClientState, enabled: bool) -> list[Any]:
        previous = client.stepping
        client.stepping = previous + 1 if enabled else max(0, previous - 1)
        if (previous > 0) != (client.stepping > 0):
            log.info(
                "client %s %s",
                client.short,
                "steps the simulation" if client.stepping else "no longer steps the simulation",
            )
        return [previous]

    def step(self, client: ClientState, _wait: Any) -> Any:
        """Wait for the next simulation step (:data:`STEP_PENDING`), as CoppeliaSim's add-on
        does for every client; a stepping client's request also lets the step happen.
        While the simulation is stopped there is no step to wait for."""
        if not self.advancing:
            return []
        client.desired_step = self.world.step_count + 1
        client.waiting = True
        return STEP_PENDING

    def advance(self) -> None:
        """One simulation step (the server calls this when the stepping gate opens)."""
        self.world.step(1)

    @property
    def step_count(self) -> int:
        return int(self.world.step_count)

    def add_log(self, client: ClientState, verbosity: int, message: str) -> list[Any]:
        level = logging.WARNING if verbosity <= _C.get("verbosity_warnings", 300) else logging.INFO
        log.log(level, "client %s: %s", client.short, message)
        return []

    def add_statusbar_message(self, client: ClientState, message: str) -> list[Any]:
        log.info("client %s: %s", client.short, message)
        return []

    # -- scripts -----------------------------------------------------------------------------
    def get_script(
        self, client: ClientState, script_type: int, handle: int, _name: Any
    ) -> list[Any]:
        if script_type != SCRIPTTYPE_CHILD:
            raise ApiError(
                f"sim.getScript: only child scripts (sim.scripttype_childscript = "
                f"{SCRIPTTYPE_CHILD}) are served, got script type {script_type}"
            )
        obj = self._object(handle, "sim.getScript")
        if not obj.model:
            owner = self.objects.bases[obj.robot].name if obj.robot is not None else None
            where = f"attached to its model base {owner}" if owner else "on the e-puck models"
            raise ApiError(f"sim.getScript: {obj.name} has no child script; the script is {where}")
        for script, robot in self.objects.scripts.items():
            if robot == obj.robot:
                return [script]
        raise ApiError(f"sim.getScript: no script for {obj.name}")  # pragma: no cover

    def call_script_function(
        self, client: ClientState, name: str, script: Any, *args: Any
    ) -> list[Any]:
        func = "sim.callScriptFunction"
        if isinstance(script, bool) or not isinstance(script, int):
            raise ApiError(
                f"bad argument #2 to '{func}' (scriptHandle: integer expected, "
                f"got {_type_name(script)})"
            )
        robot = self.objects.scripts.get(script)
        if robot is None:
            obj = self.objects.get(script)  # CoppeliaSim 4.8+: the script object's handle
            if obj is None or not obj.model:
                raise ApiError(f"{func}: script handle {script} does not exist")
            robot = obj.robot
        assert robot is not None
        if not self.script_functions:
            raise ApiError(
                f"{func}: the e-puck's script has no function {name!r} (this server serves "
                "the stock model's script, as CoppeliaSim does without puckboard's additions)"
            )
        if name == SENSE_ALL:
            return [self.sense_all(robot)]
        if name == SET_WHEELS:
            if len(args) != 2:
                raise ApiError(f"{func}: {SET_WHEELS} takes (left, right) in rad/s")
            try:
                left, right = _number(args[0]), _number(args[1])
            except TypeError:
                raise ApiError(
                    f"{func}: {SET_WHEELS} takes two numbers (rad/s), got "
                    f"{_type_name(args[0])} and {_type_name(args[1])}"
                ) from None
            self.targets[robot] = (left, right)
            self.world.set_wheel_speeds(robot, left, right)
            client.robots.add(robot)
            return []
        raise ApiError(
            f"{func}: the e-puck's script has no function {name!r}; served: "
            f"{SENSE_ALL}, {SET_WHEELS}"
        )

    def sense_all(self, robot: int) -> dict[str, Any]:
        """Every sensor of one robot in one map (V-REP order for the IR sensors)."""
        w = self.world
        order = _VREP_INDEX
        enc = w.encoders[robot]
        return {
            "api": SCRIPT_API,
            "t": float(w.time),
            "prox": w.prox_distance[robot, order].tolist(),
            "proxRaw": w.prox_raw[robot, order].tolist(),
            "range": float(w.profiles[robot].prox_range),
            "ground": w.ground[robot].tolist(),
            "joints": [
                math.remainder(float(enc[0]), math.tau),
                math.remainder(float(enc[1]), math.tau),
            ],
            "encoders": enc.tolist(),
            "speeds": w.wheel_speeds[robot].tolist(),
            "pose": w.poses[robot].tolist(),
        }


def _greyscale(handle: int) -> bool:
    """Whether a handle carries ``sim.handleflag_greyscale`` (the deprecated image calls)."""
    return handle > 0 and bool(handle & _C["handleflag_greyscale"])


def _signal_functions(
    kind: str, store: dict[str, Any], check: Callable[[Any], Any]
) -> dict[str, tuple[Handler, tuple[Param, ...]]]:
    """``sim.set/get/clear<kind>Signal`` over one of :class:`Signals`' name spaces."""

    def set_signal(client: ClientState, name: str, value: Any) -> list[Any]:
        store[name] = value
        return []

    def get_signal(client: ClientState, name: str) -> list[Any]:
        return [store.get(name)]  # None when unset, as CoppeliaSim's nil

    def clear_signal(client: ClientState, name: str) -> list[Any]:
        """One signal, or every signal of the kind when ``name`` is empty (CoppeliaSim's
        ``sim.clear*Signal()`` without a name); returns how many were cleared."""
        if not name:
            count = len(store)
            store.clear()
            return [count]
        return [1 if store.pop(name, None) is not None else 0]

    name = Param("signalName", _string)
    return {
        f"sim.set{kind}Signal": (set_signal, (name, Param("signalValue", check))),
        f"sim.get{kind}Signal": (get_signal, (name,)),
        f"sim.clear{kind}Signal": (clear_signal, (Param("signalName", _string, ""),)),
    }


def _type_name(value: Any) -> str:
    from .codec import _type_name as name

    return name(value)
