"""Poses: where a served object is, in any object's frame, and placing dummies.

Frames are full 3-D (:mod:`..frames`), in every form CoppeliaSim offers (position,
Euler angles, quaternion, 7-number pose, 12-number matrix), relative to the world, an
object's parent or any object. Robots move only through their wheels and the scene's
shapes stay where the scene puts them, so only dummies can be placed; a client trying to
move anything else is told so.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..clients import ClientState
from ..frames import Frame
from ..objects import DUMMY, ServedObject
from .checks import vector
from .names import HANDLE_PARENT, HANDLE_WORLD
from .state import ApiError, ServedState, kind_words

__all__ = ["PoseFunctions"]


class PoseFunctions(ServedState):
    """``sim.getObjectPosition`` ... ``sim.getObjectVelocity``, ``sim.setObjectPosition/Pose``."""

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
        profile = self.world.actual[i]  # the robot as built: each wheel its own radius
        left, right = self.world.wheel_speeds[i].tolist()
        radius_left, radius_right = profile.wheel_radii
        forward = (left * radius_left + right * radius_right) / 2.0
        turn = (right * radius_right - left * radius_left) / profile.axle_length
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
            if obj.robot is None:
                why = "puckboard serve keeps the scene's shapes where the scene puts them"
            else:
                robot = self.objects.bases[obj.robot].name
                part = "the served robot" if obj.model else "part of the served robot"
                why = f"it is {part} {robot}, which moves only through its wheels"
            raise ApiError(
                f"{func}: {obj.name} ({kind_words(obj.kind)}) cannot be moved: {why}; only "
                f"dummies ({', '.join(self._dummy_names()) or 'none in this scene'}) can be "
                "placed"
            )
        if isinstance(rel, bool) or not isinstance(rel, int):
            raise ApiError(
                f"bad argument #3 to '{func}' (relativeToObjectHandle: integer expected)"
            )
        return obj, value, rel

    def _dummy_names(self) -> list[str]:
        return [o.name for o in self.objects if o.kind == DUMMY]

    def set_object_position(
        self, client: ClientState, handle: int, position: Any, rel: Any
    ) -> list[Any]:
        func = "sim.setObjectPosition"
        obj, position, rel = self._movable(handle, func, position, rel)
        try:
            xyz = np.array(vector(3)(position))
        except TypeError:
            raise ApiError(
                f"bad argument #2 to '{func}' (position: array of 3 numbers expected)"
            ) from None
        ref = self._reference(obj, rel, func)
        current = self.dummy_frames[obj.handle]
        self.dummy_frames[obj.handle] = Frame(
            current.rotation, xyz if ref is None else ref.apply(xyz)
        )
        return []

    def set_object_pose(self, client: ClientState, handle: int, pose: Any, rel: Any) -> list[Any]:
        func = "sim.setObjectPose"
        obj, pose, rel = self._movable(handle, func, pose, rel)
        try:
            local = Frame.from_pose7(vector(7)(pose))
        except TypeError:
            raise ApiError(
                f"bad argument #2 to '{func}' (pose: array of 7 numbers expected)"
            ) from None
        except ValueError as exc:
            raise ApiError(f"{func}: {exc}") from None
        ref = self._reference(obj, rel, func)
        self.dummy_frames[obj.handle] = local if ref is None else ref.compose(local)
        return []
