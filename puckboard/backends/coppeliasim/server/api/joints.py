"""Joints: the wheels' target velocities, angles and speeds.

The served e-puck's only joints are its two wheel motors, always velocity-controlled as
in the stock model, so a joint handle names a robot and a side. A target set here is the
wheel command the simulation applies from its next step, and the client that set it is
remembered so its robot stops when it vanishes.
"""

from __future__ import annotations

import math
from typing import Any

from ..clients import ClientState
from ..objects import JOINT
from .state import ServedState

__all__ = ["JointFunctions"]


class JointFunctions(ServedState):
    """``sim.setJointTargetVelocity``, ``sim.getJointTargetVelocity/Position/Velocity``."""

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
