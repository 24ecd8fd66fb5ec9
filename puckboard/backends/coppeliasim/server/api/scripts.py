"""The e-puck's child script: puckboard's sense-all and set-wheels script functions.

``sim.callScriptFunction('puckboardSenseAll', sim.getScript(sim.scripttype_childscript,
ePuck))`` returns every sensor of one robot in one round trip — the thesis's
``senseAllTogether`` — and ``puckboardSetWheels(left, right)`` sets both wheels in one
(its ``setVelocitiesForRemote``). A server started without them serves the stock model's
script, as CoppeliaSim does without puckboard's additions, and clients read sensor by
sensor.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .....records import VREP_ORDER
from ..clients import ClientState
from .checks import number, type_name
from .names import SCRIPTTYPE_CHILD
from .state import ApiError, ServedState, kind_words

__all__ = ["SCRIPT_API", "SENSE_ALL", "SET_WHEELS", "ScriptFunctions"]

#: The sense-all function served as a script function of every e-puck's child script.
SENSE_ALL = "puckboardSenseAll"
#: Both wheels in one call (the thesis's ``setVelocitiesForRemote``).
SET_WHEELS = "puckboardSetWheels"
#: Version of the script functions' interface, sent in every sense-all reply as ``api``.
SCRIPT_API = 1

_VREP_INDEX = np.array(VREP_ORDER)


class ScriptFunctions(ServedState):
    """``sim.getScript``, ``sim.callScriptFunction`` and the sense-all map it returns."""

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
            raise ApiError(
                f"sim.getScript: {obj.name} ({kind_words(obj.kind)}) has no child script; "
                f"the script is {where}"
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
                f"got {type_name(script)})"
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
                left, right = number(args[0]), number(args[1])
            except TypeError:
                raise ApiError(
                    f"{func}: {SET_WHEELS} takes two numbers (rad/s), got "
                    f"{type_name(args[0])} and {type_name(args[1])}"
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
