"""Parameters: the object and simulation parameters a served scene has.

Only parameters that mean something for the served model are answered (a vision
sensor's resolution, a joint's motor, a shape's static and respondable flags, the time
step, the version); the few settable ones change nothing the robots sense. Anything else
is refused with the list of what is served, rather than answered with a made-up value.
"""

from __future__ import annotations

from typing import Any

from ..clients import ClientState
from ..objects import JOINT, VISION_SENSOR
from ..vision import resolution
from .names import CONSTANTS as _C
from .names import PROGRAM_REVISION, PROGRAM_VERSION
from .state import ApiError, ServedState

__all__ = ["ParameterFunctions"]


class ParameterFunctions(ServedState):
    """``sim.get/setObjectInt32Param``, ``sim.get/setInt32Param``, ``sim.getFloat/BoolParam``."""

    def get_object_int32_param(self, client: ClientState, handle: int, param: int) -> list[Any]:
        func = "sim.getObjectInt32Param"
        obj = self._object(handle, func)
        if param == _C["objintparam_visibility_layer"]:
            return [self._visibility.get(obj.handle, 1)]
        if obj.kind == VISION_SENSOR and param == _C["visionintparam_resolution_x"]:
            return [resolution(obj.part, self.scene)[0]]
        if obj.kind == VISION_SENSOR and param == _C["visionintparam_resolution_y"]:
            return [resolution(obj.part, self.scene)[1]]
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
