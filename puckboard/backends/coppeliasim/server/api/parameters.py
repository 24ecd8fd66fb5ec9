"""Parameters: the object and simulation parameters a served scene has.

Only parameters that mean something for the served model are answered (a vision
sensor's resolution, a joint's motor, a shape's static and respondable flags, the time
step, the version); anything else is refused with the object's kind and the list of
what is served for it, rather than answered with a made-up value.

Setting an object parameter is accepted in two cases. The value the served model
already has (a wheel motor enabled, its position control off) changes nothing, as in
CoppeliaSim. A *visual-only* parameter — one that in CoppeliaSim 4.7 changes only what
its GUI draws, never physics, a sensor's reading or a vision sensor's image — is accepted
and has no effect, because the stand-in draws nothing: clients set them routinely (hiding
the proximity sensors' rays is the classic) and must not fail here where CoppeliaSim
succeeds. The list is CoppeliaSim 4.7's ``simSetObjectInt32Param_internal``
(coppeliaSimLib ``interfaces/simInternal.cpp``) filtered by where each value is read:

* ``sim.objintparam_visibility_layer`` (any object): the layers the scene views show;
  vision sensors render with ``sim.displayattribute_ignorelayer`` by default, so it does
  not change their images. Kept (0…65535, as CoppeliaSim clamps it) and read back;
* ``sim.objintparam_hierarchycolor`` (any object): the colour of its row in the scene
  hierarchy window;
* ``sim.proxintparam_ray_invisibility`` (proximity sensors): whether the detection ray
  is drawn (read only by the sensor's rendering);
* ``sim.visionintparam_windowed_size_x/_y``, ``…_pos_x/_y`` (vision sensors): the size
  and place of the floating window that shows the sensor's image.

Parameters that look cosmetic but change what a vision sensor sees (a shape's culling,
wireframe or edges, a vision sensor's render mode, an object's illumination) are not in
the list: the stand-in cannot honour them, so they are refused.
"""

from __future__ import annotations

import re
from typing import Any

from ..clients import ClientState
from ..objects import DUMMY, JOINT, LIGHT, PROXIMITY_SENSOR, SHAPE, VISION_SENSOR, ServedObject
from ..vision import resolution
from .names import CONSTANTS as _C
from .names import PROGRAM_REVISION, PROGRAM_VERSION
from .state import ApiError, ServedState, kind_words

__all__ = ["VISUAL_ONLY", "ParameterFunctions"]

#: Visual-only object parameters (see the module docstring), by the object kind they
#: apply to (``None``: every object).
VISUAL_ONLY: dict[str | None, tuple[str, ...]] = {
    None: ("objintparam_visibility_layer", "objintparam_hierarchycolor"),
    PROXIMITY_SENSOR: ("proxintparam_ray_invisibility",),
    VISION_SENSOR: (
        "visionintparam_windowed_size_x", "visionintparam_windowed_size_y",
        "visionintparam_windowed_pos_x", "visionintparam_windowed_pos_y",
    ),
}  # fmt: skip

#: Object parameters ``sim.getObjectInt32Param`` answers, by object kind.
_READABLE: dict[str | None, tuple[str, ...]] = {
    None: ("objintparam_visibility_layer",),
    VISION_SENSOR: ("visionintparam_resolution_x", "visionintparam_resolution_y"),
    JOINT: ("jointintparam_motor_enabled", "jointintparam_ctrl_enabled"),
    SHAPE: ("shapeintparam_static", "shapeintparam_respondable"),
}

#: What a served joint (a wheel motor, velocity-controlled) already is: setting these
#: values changes nothing, so CoppeliaSim accepts them and so do we.
_JOINT_AS_IS = {
    "jointintparam_motor_enabled": ("1", 1),
    "jointintparam_ctrl_enabled": ("0", 0),
    "jointintparam_dynctrlmode": ("sim.jointdynctrl_velocity", _C["jointdynctrl_velocity"]),
}

#: Why the parameters of each kind of object are fixed here.
_FIXED_BECAUSE = {
    JOINT: "the served joints are the robots' wheel motors, always velocity-controlled",
    PROXIMITY_SENSOR: "the served IR sensors' volume and what they detect are the model's",
    VISION_SENSOR: "the served vision sensors' resolution and rendering are the model's",
    SHAPE: "the served shapes' dynamics and looks are fixed by the model and the scene",
    DUMMY: "a served dummy is a marker: only its pose can be set (sim.setObjectPose)",
    LIGHT: "the served LED light is the model's",
}

#: The prefix of each kind's own parameters (``sim.proxintparam_*`` ...).
_PREFIX = {
    SHAPE: "shape", JOINT: "joint", PROXIMITY_SENSOR: "prox", VISION_SENSOR: "vision",
    DUMMY: "dummy", LIGHT: "light",
}  # fmt: skip
_KIND_OF_PREFIX = {prefix: kind for kind, prefix in _PREFIX.items()}
_OBJECT_INT_PARAM = re.compile(r"^([a-z]+)intparam_")


def _for_kind(table: dict[str | None, tuple[str, ...]], kind: str) -> tuple[str, ...]:
    return table[None] + table.get(kind, ())


def _listed(names: tuple[str, ...]) -> str:
    return ", ".join(f"sim.{n}" for n in names)


def parameter_name(param: int, kind: str) -> tuple[str, str | None]:
    """``param`` as a client writes it, ``4000 (sim.proxintparam_ray_invisibility)``, and
    the kind of object whose parameter that is (``None``: any object's, or unknown). The
    numbers of different kinds overlap, so ``kind``'s own names are preferred."""
    names = {n: m[1] for n, v in _C.items() if v == param and (m := _OBJECT_INT_PARAM.match(n))}
    if not names:
        return str(param), None
    own = [n for n, prefix in names.items() if prefix in (_PREFIX.get(kind), "obj")]
    name = (own or list(names))[0]
    owner = _KIND_OF_PREFIX.get(names[name], names[name]) if names[name] != "obj" else None
    return f"{param} (sim.{name})", owner


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
        if obj.kind == SHAPE and param == _C["shapeintparam_static"]:
            return [0 if obj.robot is not None else 1]
        if obj.kind == SHAPE and param == _C["shapeintparam_respondable"]:
            return [1 if obj.part in ("base", "obstacle", "wall", "floor") else 0]
        name, owner = parameter_name(param, obj.kind)
        raise ApiError(
            f"{func}: parameter {name} of {_named(obj)} is not served{_whose(owner, obj)}; "
            f"served for {kind_words(obj.kind)}: {_listed(_for_kind(_READABLE, obj.kind))}"
        )

    def set_object_int32_param(
        self, client: ClientState, handle: int, param: int, value: int
    ) -> list[Any]:
        func = "sim.setObjectInt32Param"
        obj = self._object(handle, func)
        if param == _C["objintparam_visibility_layer"]:
            self._visibility[obj.handle] = min(max(value, 0), 65535)  # CoppeliaSim clamps
            return []
        if param in (_C[n] for n in _for_kind(VISUAL_ONLY, obj.kind)):
            return []  # only what CoppeliaSim's GUI draws: nothing to draw here
        if obj.kind == JOINT and any(
            param == _C[n] and value == v for n, (_, v) in _JOINT_AS_IS.items()
        ):  # fmt: skip
            return []  # what the wheel motor already is
        settable = _listed(_for_kind(VISUAL_ONLY, obj.kind)) + " (visual only)"
        if obj.kind == JOINT:
            settable += ", " + ", ".join(f"sim.{n} = {v}" for n, (v, _) in _JOINT_AS_IS.items())
        name, owner = parameter_name(param, obj.kind)
        why = _whose(owner, obj) or ": " + _FIXED_BECAUSE.get(obj.kind, "the model is fixed")
        raise ApiError(
            f"{func}: cannot set parameter {name} of {_named(obj)} to {value}{why}; "
            f"settable on {kind_words(obj.kind)}: {settable}"
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


def _whose(owner: str | None, obj: ServedObject) -> str:
    """``: it is a proximity sensor's parameter`` when the parameter is another kind's."""
    if owner in (None, obj.kind):
        return ""
    return f": it is {kind_words(owner)}'s parameter, and {obj.name} is {kind_words(obj.kind)}"


def _named(obj: ServedObject) -> str:
    """``ePuck_proxSensor1 (a proximity sensor)``: a refusal says what the object is."""
    return f"{obj.name} ({kind_words(obj.kind)})"
