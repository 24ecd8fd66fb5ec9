"""SimApi: the ``sim.*`` functions this server serves, over a :class:`~puckboard.sim.world.World`.

The dispatch table :attr:`SimApi.functions` is the whole surface a client can reach: it
is written out once, here, function by function, and a function is reached only through
it — never by a Python name a client sends. Every argument is checked against the
function's parameter list before anything runs (:mod:`.api.checks`). Nothing a client
sends is ever executed or evaluated.

The functions themselves live in one module per group of CoppeliaSim's manual
(:mod:`.api`), each a mixin over the shared served state, which :class:`SimApi`
composes. Return values follow the CoppeliaSim manual (``manual.coppeliarobotics.com``,
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

``zmqRemoteApi.info('sim')`` lists CoppeliaSim's whole ``sim`` namespace
(:mod:`.api.names`), so that a function we do not serve reaches the server and is
answered with what it is and what is served. Stepping (``sim.setStepping``/``sim.step``)
needs the client table and is finished by the server; see :mod:`.clients`.
"""

from __future__ import annotations

import difflib
from typing import TYPE_CHECKING, Any

import numpy as np

from .api.checks import (
    Handler,
    Param,
    anything,
    boolean,
    buffer,
    check_args,
    int_pair,
    integer,
    number,
    options_map,
    string,
)
from .api.joints import JointFunctions
from .api.names import CONSTANTS, HANDLE_ALL, HANDLE_WORLD, NAMES
from .api.parameters import ParameterFunctions
from .api.poses import PoseFunctions
from .api.scene_tree import SceneTreeFunctions
from .api.scripts import ScriptFunctions
from .api.sensors import SensorFunctions
from .api.signals import signal_functions
from .api.simulation import SimulationFunctions
from .api.state import ApiError, Signals
from .clients import ClientState
from .objects import SceneObjects

if TYPE_CHECKING:
    from ....scenario.scene import Scene

__all__ = ["SimApi"]


class SimApi(
    SceneTreeFunctions,
    PoseFunctions,
    JointFunctions,
    SensorFunctions,
    ParameterFunctions,
    SimulationFunctions,
    ScriptFunctions,
):
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
        self.world = World(scene, seed=seed)
        self.objects = SceneObjects(
            self.world.actual, labels=self.world.robot_names, model=model, scene=scene
        )
        n = len(self.world.robot_names)
        self.targets = np.zeros((n, 2))
        self.running = False
        self.paused = False
        self.signals = Signals()
        self.dummy_frames = {}
        self._visibility = {}
        self._int_params = {CONSTANTS["intparam_idle_fps"]: 8}
        self._restore_scene_state()
        self.functions: dict[str, tuple[Handler, tuple[Param, ...]]] = self._table()
        self._coppeliasim = frozenset("sim." + f for f in NAMES["functions"])

    # -- the dispatch table ------------------------------------------------------------------
    def _table(self) -> dict[str, tuple[Handler, tuple[Param, ...]]]:
        P = Param
        handle = P("objectHandle", integer)
        rel = P("relativeToObjectHandle", integer, HANDLE_WORLD)
        img_args = (
            P("sensorHandle", integer),
            P("options", integer, 0),
            P("rgbaCutOff", number, 0.0),
            P("pos", int_pair, (0, 0)),
            P("size", int_pair, (0, 0)),
        )
        return {
            # the scene tree
            "sim.getObject": (
                self.get_object,
                (P("objectPath", string), P("options", options_map, {})),
            ),
            "sim.getObjectHandle": (self.get_object_handle, (P("objectName", string),)),
            "sim.getObjectAlias": (self.get_object_alias, (handle, P("options", integer, -1))),
            "sim.getObjectName": (self.get_object_name, (handle,)),
            "sim.getObjectType": (self.get_object_type, (handle,)),
            "sim.getObjectParent": (self.get_object_parent, (handle,)),
            "sim.getObjectChild": (self.get_object_child, (handle, P("index", integer))),
            "sim.getObjectsInTree": (
                self.get_objects_in_tree,
                (
                    P("treeBaseHandle", integer),
                    P("objectType", integer, HANDLE_ALL),
                    P("options", integer, 0),
                ),
            ),
            "sim.getObjects": (self.get_objects, (P("index", integer), P("objectType", integer))),
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
            "sim.setObjectPosition": (
                self.set_object_position,
                (
                    handle,
                    P("position", anything),
                    P("relativeToObjectHandle", anything, HANDLE_WORLD),
                ),
            ),
            "sim.setObjectPose": (
                self.set_object_pose,
                (handle, P("pose", anything), P("relativeToObjectHandle", anything, HANDLE_WORLD)),
            ),
            # joints
            "sim.setJointTargetVelocity": (
                self.set_joint_target_velocity,
                (
                    P("jointHandle", integer),
                    P("targetVelocity", number),
                    P("params", anything, None),
                ),
            ),
            "sim.getJointTargetVelocity": (
                self.get_joint_target_velocity,
                (P("jointHandle", integer),),
            ),
            "sim.getJointPosition": (self.get_joint_position, (P("jointHandle", integer),)),
            "sim.getJointVelocity": (self.get_joint_velocity, (P("jointHandle", integer),)),
            # sensors
            "sim.readProximitySensor": (self.read_proximity_sensor, (P("sensorHandle", integer),)),
            "sim.handleProximitySensor": (
                self.read_proximity_sensor,
                (P("sensorHandle", integer),),
            ),
            "sim.readVisionSensor": (self.read_vision_sensor, (P("sensorHandle", integer),)),
            "sim.handleVisionSensor": (self.handle_vision_sensor, (P("sensorHandle", integer),)),
            "sim.getVisionSensorRes": (self.get_vision_sensor_res, (P("sensorHandle", integer),)),
            "sim.getVisionSensorImg": (self.get_vision_sensor_img, img_args),
            "sim.getVisionSensorCharImage": (
                self.get_vision_sensor_char_image,
                (
                    P("sensorHandle", integer),
                    P("posX", integer, 0),
                    P("posY", integer, 0),
                    P("sizeX", integer, 0),
                    P("sizeY", integer, 0),
                    P("rgbaCutOff", number, 0.0),
                ),
            ),
            "sim.getVisionSensorImage": (
                self.get_vision_sensor_image,
                (
                    P("sensorHandle", integer),
                    P("posX", integer, 0),
                    P("posY", integer, 0),
                    P("sizeX", integer, 0),
                    P("sizeY", integer, 0),
                    P("returnType", integer, 0),
                ),
            ),
            # parameters
            "sim.getObjectInt32Param": (
                self.get_object_int32_param,
                (handle, P("parameterID", integer)),
            ),
            "sim.setObjectInt32Param": (
                self.set_object_int32_param,
                (handle, P("parameterID", integer), P("parameter", integer)),
            ),
            "sim.getInt32Param": (self.get_int32_param, (P("parameter", integer),)),
            "sim.setInt32Param": (
                self.set_int32_param,
                (P("parameter", integer), P("intState", integer)),
            ),
            "sim.getFloatParam": (self.get_float_param, (P("parameter", integer),)),
            "sim.getBoolParam": (self.get_bool_param, (P("parameter", integer),)),
            # signals
            **signal_functions("String", self.signals.string, buffer),
            **signal_functions("Int32", self.signals.int32, integer),
            **signal_functions("Float", self.signals.float, number),
            # the simulation
            "sim.getSimulationTime": (self.get_simulation_time, ()),
            "sim.getSimulationTimeStep": (self.get_simulation_time_step, ()),
            "sim.getSimulationState": (self.get_simulation_state, ()),
            "sim.getSystemTime": (self.get_system_time, ()),
            "sim.startSimulation": (self.start_simulation, ()),
            "sim.pauseSimulation": (self.pause_simulation, ()),
            "sim.stopSimulation": (self.stop_simulation, (P("wait", anything, None),)),
            "sim.setStepping": (self.set_stepping, (P("enabled", boolean),)),
            "sim.step": (self.step, (P("wait", anything, None),)),
            "sim.addLog": (self.add_log, (P("verbosityLevel", integer), P("logMessage", string))),
            "sim.addStatusbarMessage": (self.add_statusbar_message, (P("message", string),)),
            # scripts
            "sim.getScript": (
                self.get_script,
                (
                    P("scriptType", integer),
                    P("objectHandle", integer, -1),
                    P("scriptName", anything, None),
                ),
            ),
            "sim.callScriptFunction": (
                self.call_script_function,
                (P("functionName", string), P("scriptHandle", anything)),
            ),
        }

    def info(self) -> dict[str, Any]:
        """What ``zmqRemoteApi.info('sim')`` returns: CoppeliaSim's whole ``sim`` namespace
        (functions and constants), so that unserved functions reach the server."""
        out: dict[str, Any] = {name: {"func": {}} for name in NAMES["functions"]}
        for name in self.functions:
            out[name.removeprefix("sim.")] = {"func": {}}
        for name, value in CONSTANTS.items():
            out[name] = {"const": value}
        return out

    def call(self, client: ClientState, func: str, args: list[Any]) -> Any:
        """Run ``func`` for ``client``: a list of return values, or
        :data:`~.api.state.STEP_PENDING`.

        Raises :class:`ApiError` for unknown functions and bad arguments.
        """
        entry = self.functions.get(func)
        if entry is None:
            raise ApiError(self._unknown(func))
        handler, params = entry
        values = check_args(func, params, args)
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
