"""The ``sim.*`` functions this server serves, over a :class:`~puckboard.sim.world.World`.

The dispatch table :data:`SimApi.FUNCTIONS` is the whole surface a client can reach: a
name that is not in it gets ``No such function: <name>``, and every argument is checked
against the function's parameter list before anything runs (``bad argument #2 to
'sim.setJointTargetVelocity' (velocity: number expected, got text string)``). Nothing a
client sends is ever executed or evaluated.

Return values follow the CoppeliaSim manual (``manual.coppeliarobotics.com``,
``regularApi/sim<Name>.htm``) so that a controller written for CoppeliaSim runs
unchanged. Where the served simulator differs from CoppeliaSim, it is said here:

* ``sim.getJointPosition`` wraps to (-π, π], as for CoppeliaSim's cyclic revolute joints.
* ``sim.readProximitySensor`` returns ``(1, d, [0, 0, d], -1, [0, 0, -1])`` when the
  sensor sees something at ``d`` m (the detected object's handle is not tracked: -1),
  and ``(0, 0.0, [0, 0, 0], -1, [0, 0, 0])`` otherwise.
* ``ePuck_lightSensor`` is a 3×1 vision sensor whose pixels are the floor brightness
  under the left, centre and right ground sensors (grey, 0..255): that is how the
  V-REP model's line follower reads three pixels of its light sensor. For the exact
  values, the sense-all script function returns them as floats.
* Vision sensor images come bottom row first, RGB, 3 bytes a pixel (1 with option bit 0
  set: greyscale), as CoppeliaSim sends them.
* Every served object's orientation is a rotation about the vertical axis only.
* ``sim.stopSimulation`` restores the scene's initial state, as CoppeliaSim does.
* The script function ``puckboardSenseAll`` (``sim.callScriptFunction('puckboardSenseAll',
  sim.getScript(sim.scripttype_childscript, ePuck))``) returns every sensor of one robot
  in one round trip — the thesis's ``senseAllTogether`` — and ``puckboardSetWheels(left,
  right)`` sets both wheels in one (its ``setVelocitiesForRemote``). docs/coppeliasim.md
  gives the Lua for CoppeliaSim.

Stepping (``sim.setStepping``/``sim.step``) needs the client table and is finished by
the server; see :mod:`.clients`.
"""

from __future__ import annotations

import difflib
import logging
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..records import VREP_ORDER
from .clients import ClientState
from .objects import (
    JOINT,
    MODEL,
    PROXIMITY_SENSOR,
    VISION_SENSOR,
    ObjectNotFound,
    SceneObjects,
    ServedObject,
)

if TYPE_CHECKING:
    from ..scenario.scene import Scene
    from ..sim.world import World

__all__ = ["CONSTANTS", "ApiError", "SimApi", "StepPending"]

log = logging.getLogger(__name__)

# CoppeliaSim's constants for the functions we serve.
HANDLE_WORLD = -1
HANDLE_PARENT = -11
SCRIPTTYPE_CHILD = 1
SIMULATION_STOPPED = 0
SIMULATION_PAUSED = 8
SIMULATION_ADVANCING_RUNNING = 0x11

CONSTANTS: dict[str, int] = {
    "handle_world": HANDLE_WORLD,
    "handle_parent": HANDLE_PARENT,
    "scripttype_childscript": SCRIPTTYPE_CHILD,
    "scripttype_simulation": SCRIPTTYPE_CHILD,
    "simulation_stopped": SIMULATION_STOPPED,
    "simulation_paused": SIMULATION_PAUSED,
    "simulation_advancing": 0x10,
    "simulation_advancing_running": SIMULATION_ADVANCING_RUNNING,
}

#: The sense-all function served as a script function of every e-puck's child script.
SENSE_ALL = "puckboardSenseAll"
#: Both wheels in one call (the thesis's ``setVelocitiesForRemote``).
SET_WHEELS = "puckboardSetWheels"
#: Version of the script functions' interface, sent in every sense-all reply as ``api``.
SCRIPT_API = 1
#: Resolution of the served light (ground) sensor.
LIGHT_SENSOR_RES = (3, 1)


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


@dataclass(frozen=True)
class Param:
    name: str
    check: Callable[[Any], Any]
    default: Any = _REQUIRED


Handler = Callable[..., Any]


class SimApi:
    """The served functions and the state they act on (one world, its objects).

    Only the server thread calls into it, so it holds no lock. ``reset()`` rebuilds the
    world from the scene with the same seed (``sim.stopSimulation``).
    """

    def __init__(self, scene: Scene, *, seed: int = 0, model: str = "ePuck") -> None:
        from ..sim.world import World

        self.scene = scene
        self.seed = seed
        self._world_class = World
        self.world: World = World(scene, seed=seed)
        self.objects = SceneObjects(self.world.profiles, labels=self.world.robot_names, model=model)
        n = len(self.world.robot_names)
        self.targets = np.zeros((n, 2))
        self.running = False
        self.functions: dict[str, tuple[Handler, tuple[Param, ...]]] = self._table()

    # -- the dispatch table ------------------------------------------------------------------
    def _table(self) -> dict[str, tuple[Handler, tuple[Param, ...]]]:
        P = Param
        handle = P("objectHandle", _int)
        rel = P("relativeToObjectHandle", _int, HANDLE_WORLD)
        return {
            "sim.getObject": (
                self.get_object, (P("objectPath", _string), P("options", _options, {}))
            ),
            "sim.getObjectHandle": (self.get_object_handle, (P("objectName", _string),)),
            "sim.getObjectAlias": (
                self.get_object_alias, (handle, P("options", _int, -1))
            ),
            "sim.setJointTargetVelocity": (
                self.set_joint_target_velocity,
                (P("jointHandle", _int), P("targetVelocity", _number), P("params", _anything, None)),
            ),
            "sim.getJointTargetVelocity": (self.get_joint_target_velocity, (P("jointHandle", _int),)),
            "sim.getJointPosition": (self.get_joint_position, (P("jointHandle", _int),)),
            "sim.getJointVelocity": (self.get_joint_velocity, (P("jointHandle", _int),)),
            "sim.readProximitySensor": (self.read_proximity_sensor, (P("sensorHandle", _int),)),
            "sim.getVisionSensorRes": (self.get_vision_sensor_res, (P("sensorHandle", _int),)),
            "sim.getVisionSensorImg": (
                self.get_vision_sensor_img,
                (
                    P("sensorHandle", _int),
                    P("options", _int, 0),
                    P("rgbaCutOff", _number, 0.0),
                    P("pos", _int_pair, (0, 0)),
                    P("size", _int_pair, (0, 0)),
                ),
            ),
            "sim.getObjectPosition": (self.get_object_position, (handle, rel)),
            "sim.getObjectOrientation": (self.get_object_orientation, (handle, rel)),
            "sim.getObjectPose": (self.get_object_pose, (handle, rel)),
            "sim.getSimulationTime": (self.get_simulation_time, ()),
            "sim.getSimulationTimeStep": (self.get_simulation_time_step, ()),
            "sim.getSimulationState": (self.get_simulation_state, ()),
            "sim.startSimulation": (self.start_simulation, ()),
            "sim.stopSimulation": (self.stop_simulation, ()),
            "sim.setStepping": (self.set_stepping, (P("enabled", _boolean),)),
            "sim.step": (self.step, (P("wait", _anything, None),)),
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
        """What ``zmqRemoteApi.info('sim')`` returns: served functions and constants."""
        out: dict[str, Any] = {}
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
        close = difflib.get_close_matches(func, list(self.functions), n=2, cutoff=0.75)
        hint = f"; did you mean {' or '.join(close)}?" if close else ""
        return (
            f"No such function: {func}{hint} (this server serves "
            f"{len(self.functions)} sim.* functions; zmqRemoteApi.info('sim') lists them)"
        )

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
        obj = self.objects.get(handle)
        if obj is None:
            raise ApiError(f"{func}: object handle {handle} does not exist")
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
        return [obj.alias if options == -1 else self.objects.alias_path(obj)]

    # -- joints ------------------------------------------------------------------------------
    def set_joint_target_velocity(
        self, client: ClientState, handle: int, velocity: float, _params: Any
    ) -> list[Any]:
        obj = self._object(handle, "sim.setJointTargetVelocity", JOINT)
        self.targets[obj.robot, obj.index] = velocity
        left, right = self.targets[obj.robot].tolist()
        self.world.set_wheel_speeds(obj.robot, left, right)
        client.robots.add(obj.robot)
        return []

    def get_joint_target_velocity(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.getJointTargetVelocity", JOINT)
        return [float(self.targets[obj.robot, obj.index])]

    def get_joint_position(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.getJointPosition", JOINT)
        return [math.remainder(float(self.world.encoders[obj.robot, obj.index]), math.tau)]

    def get_joint_velocity(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.getJointVelocity", JOINT)
        return [float(self.world.wheel_speeds[obj.robot, obj.index])]

    def stop_robot(self, robot: int) -> None:
        """Zero a robot's wheel targets (a vanished client's robot)."""
        self.targets[robot] = 0.0
        self.world.set_wheel_speeds(robot, 0.0, 0.0)

    # -- sensors -----------------------------------------------------------------------------
    def read_proximity_sensor(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.readProximitySensor", PROXIMITY_SENSOR)
        i = obj.robot
        d = float(self.world.prox_distance[i, VREP_ORDER[obj.index]])
        if d < self.world.profiles[i].prox_range:
            return [1, d, [0.0, 0.0, d], -1, [0.0, 0.0, -1.0]]
        return [0, 0.0, [0.0, 0.0, 0.0], -1, [0.0, 0.0, 0.0]]

    def _resolution(self, obj: ServedObject) -> tuple[int, int]:
        if obj.part == "light":
            return LIGHT_SENSOR_RES
        w, h = self.scene.camera_size
        return int(w), int(h)

    def get_vision_sensor_res(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.getVisionSensorRes", VISION_SENSOR)
        return [list(self._resolution(obj))]

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
        w, h = self._resolution(obj)
        if obj.part == "light":
            grey = np.rint(self.world.ground[obj.robot] * 255.0).astype(np.uint8)
            upright = np.repeat(grey[None, :, None], 3, axis=2)
        else:
            upright = self.world.render_camera(obj.robot)
        image = upright[::-1]  # CoppeliaSim sends the bottom row first
        x, y = pos
        sw, sh = size
        if (sw, sh) != (0, 0):
            if x < 0 or y < 0 or sw <= 0 or sh <= 0 or x + sw > w or y + sh > h:
                raise ApiError(
                    f"{func}: window pos={list(pos)} size={list(size)} lies outside the "
                    f"{w}×{h} image"
                )
            image = image[y : y + sh, x : x + sw]
        if options & 1:
            image = np.rint(image.mean(axis=2)).astype(np.uint8)
        return [np.ascontiguousarray(image).tobytes(), [int(image.shape[1]), int(image.shape[0])]]

    # -- poses -------------------------------------------------------------------------------
    def _world_pose(self, obj: ServedObject) -> tuple[float, float, float, float]:
        bx, by, bth = self.world.poses[obj.robot].tolist()
        ox, oy, oz, oyaw = obj.offset
        c, s = math.cos(bth), math.sin(bth)
        return bx + c * ox - s * oy, by + s * ox + c * oy, oz, bth + oyaw

    def _relative_pose(self, handle: int, rel: int, func: str) -> tuple[float, float, float, float]:
        obj = self._object(handle, func)
        x, y, z, yaw = self._world_pose(obj)
        if rel == HANDLE_WORLD:
            ref = None
        elif rel == HANDLE_PARENT:
            ref = self.objects.get(obj.parent) if obj.parent is not None else None
        else:
            ref = self._object(rel, func)
        if ref is not None:
            rx, ry, rz, ryaw = self._world_pose(ref)
            c, s = math.cos(ryaw), math.sin(ryaw)
            dx, dy = x - rx, y - ry
            x, y, z, yaw = c * dx + s * dy, -s * dx + c * dy, z - rz, yaw - ryaw
        return x, y, z, math.remainder(yaw, math.tau)

    def get_object_position(self, client: ClientState, handle: int, rel: int) -> list[Any]:
        x, y, z, _ = self._relative_pose(handle, rel, "sim.getObjectPosition")
        return [[x, y, z]]

    def get_object_orientation(self, client: ClientState, handle: int, rel: int) -> list[Any]:
        *_, yaw = self._relative_pose(handle, rel, "sim.getObjectOrientation")
        return [[0.0, 0.0, yaw]]

    def get_object_pose(self, client: ClientState, handle: int, rel: int) -> list[Any]:
        x, y, z, yaw = self._relative_pose(handle, rel, "sim.getObjectPose")
        return [[x, y, z, 0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)]]

    # -- simulation --------------------------------------------------------------------------
    def get_simulation_time(self, client: ClientState) -> list[Any]:
        return [float(self.world.time)]

    def get_simulation_time_step(self, client: ClientState) -> list[Any]:
        return [float(self.world.dt)]

    def get_simulation_state(self, client: ClientState) -> list[Any]:
        return [SIMULATION_ADVANCING_RUNNING if self.running else SIMULATION_STOPPED]

    def start_simulation(self, client: ClientState) -> list[Any]:
        if not self.running:
            self.running = True
            self.world.start()
            log.info("simulation started by client %s", client.short)
        return [1]

    def stop_simulation(self, client: ClientState) -> list[Any]:
        """Stop and restore the initial scene (the server releases waiting clients)."""
        if self.running:
            log.info(
                "simulation stopped by client %s at t=%.2f s; scene restored",
                client.short,
                self.world.time,
            )
        self.running = False
        self.reset()
        return [1]

    def reset(self) -> None:
        self.world = self._world_class(self.scene, seed=self.seed)
        self.targets[:] = 0.0

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
        """Ask for one more step; :data:`STEP_PENDING` when the client must wait for it."""
        if not self.running or client.stepping <= 0:
            return []  # as CoppeliaSim: nothing to wait for
        client.desired_step = self.world.step_count + 1
        client.waiting = True
        return STEP_PENDING

    def advance(self) -> None:
        """One simulation step (the server calls this when the stepping gate opens)."""
        self.world.step(1)

    @property
    def step_count(self) -> int:
        return int(self.world.step_count)

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
        if obj.kind != MODEL:
            raise ApiError(
                f"sim.getScript: {obj.name} has no child script; the e-puck's script is "
                f"attached to its model base {self.objects.bases[obj.robot].name}"
            )
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
            if obj is None or obj.kind != MODEL:
                raise ApiError(f"{func}: script handle {script} does not exist")
            robot = obj.robot
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


def _type_name(value: Any) -> str:
    from .codec import _type_name as name

    return name(value)
