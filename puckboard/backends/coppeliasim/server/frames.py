"""Rigid transforms in 3-D, in the forms CoppeliaSim's API speaks.

The embedded world is planar, but the objects ``puckboard serve`` stands in for are not:
a proximity sensor's frame has its z axis along the direction it looks (so the detected
point it reports, ``[0, 0, d]`` straight ahead, is a point in that frame), the ground
sensor looks down, a wheel turns about its joint's z axis. A client that multiplies
``sim.getObjectMatrix(sensor)`` by the detected point must land on the obstacle, so every
served object carries a full rotation, and poses go out as CoppeliaSim returns them:

* ``sim.getObjectMatrix``: 12 numbers, the 3×4 matrix ``[R | t]`` row by row;
* ``sim.getObjectQuaternion`` and the last four of ``sim.getObjectPose``: ``[qx, qy, qz, qw]``;
* ``sim.getObjectOrientation``: Euler angles ``[α, β, γ]`` with ``R = Rx(α)·Ry(β)·Rz(γ)``
  (CoppeliaSim's convention; for a robot on the floor α = β = 0 and γ is its heading).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

__all__ = ["IDENTITY", "Frame", "frame_from_axes", "rotation_z"]

Matrix = npt.NDArray[np.float64]


def rotation_z(angle: float) -> Matrix:
    """Rotation by ``angle`` (rad) about z."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


@dataclass(frozen=True, eq=False)
class Frame:
    """A pose: ``rotation`` (3×3, columns are the frame's axes in the parent frame) and
    ``position`` (3, m) of the origin in the parent frame."""

    rotation: Matrix
    position: Matrix

    @classmethod
    def planar(cls, x: float, y: float, heading: float, z: float = 0.0) -> Frame:
        """A frame on a horizontal plane, turned by ``heading`` about the vertical."""
        return cls(rotation_z(heading), np.array([x, y, z], dtype=float))

    def compose(self, local: Frame) -> Frame:
        """``local`` (given in this frame) expressed in this frame's parent."""
        return Frame(self.rotation @ local.rotation, self.rotation @ local.position + self.position)

    def inverse(self) -> Frame:
        rt = self.rotation.T
        return Frame(rt, -(rt @ self.position))

    def relative_to(self, reference: Frame) -> Frame:
        """This frame seen from ``reference`` (both given in the same parent)."""
        return reference.inverse().compose(self)

    def apply(self, point: Matrix) -> Matrix:
        """A point given in this frame, expressed in the parent."""
        return self.rotation @ np.asarray(point, dtype=float) + self.position

    def matrix12(self) -> list[float]:
        """``[R | t]`` row by row, as ``sim.getObjectMatrix`` returns it."""
        return np.hstack([self.rotation, self.position[:, None]]).ravel().tolist()

    def euler(self) -> list[float]:
        """CoppeliaSim's Euler angles ``[α, β, γ]``: ``R = Rx(α)·Ry(β)·Rz(γ)``."""
        r = self.rotation
        beta = math.asin(max(-1.0, min(1.0, float(r[0, 2]))))
        if abs(r[0, 2]) < 1.0 - 1e-12:
            alpha = math.atan2(-float(r[1, 2]), float(r[2, 2]))
            gamma = math.atan2(-float(r[0, 1]), float(r[0, 0]))
        else:  # gimbal lock: only α + γ (or α − γ) is defined; put it all in α
            alpha = math.atan2(float(r[2, 1]), float(r[1, 1]))
            gamma = 0.0
        return [alpha, beta, gamma]

    def quaternion(self) -> list[float]:
        """``[qx, qy, qz, qw]`` with ``qw >= 0`` (Shepperd's method, stable for any rotation)."""
        r = self.rotation
        trace = float(r[0, 0] + r[1, 1] + r[2, 2])
        if trace > 0.0:
            s = 2.0 * math.sqrt(trace + 1.0)
            q = [(r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, s / 4]
        elif r[0, 0] > r[1, 1] and r[0, 0] > r[2, 2]:
            s = 2.0 * math.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2])
            q = [s / 4, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s, (r[2, 1] - r[1, 2]) / s]
        elif r[1, 1] > r[2, 2]:
            s = 2.0 * math.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2])
            q = [(r[0, 1] + r[1, 0]) / s, s / 4, (r[1, 2] + r[2, 1]) / s, (r[0, 2] - r[2, 0]) / s]
        else:
            s = 2.0 * math.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1])
            q = [(r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, s / 4, (r[1, 0] - r[0, 1]) / s]
        sign = -1.0 if q[3] < 0 else 1.0
        return [sign * float(v) for v in q]

    def pose7(self) -> list[float]:
        """``[x, y, z, qx, qy, qz, qw]``, as ``sim.getObjectPose`` returns it."""
        return [*self.position.tolist(), *self.quaternion()]

    @classmethod
    def from_pose7(cls, pose: list[float]) -> Frame:
        """The frame of ``[x, y, z, qx, qy, qz, qw]`` (:meth:`pose7`'s inverse); the
        quaternion is normalised first. Raises ``ValueError`` for a zero quaternion."""
        x, y, z, qx, qy, qz, qw = pose
        norm = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
        if norm == 0.0:
            raise ValueError("the quaternion [qx, qy, qz, qw] must not be zero")
        qx, qy, qz, qw = qx / norm, qy / norm, qz / norm, qw / norm
        rotation = np.array([
            [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
            [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
            [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)],
        ])  # fmt: skip
        return cls(rotation, np.array([x, y, z], dtype=float))


def frame_from_axes(
    x_axis: tuple[float, float, float],
    y_axis: tuple[float, float, float],
    z_axis: tuple[float, float, float],
    position: tuple[float, float, float] = (0.0, 0.0, 0.0),
) -> Frame:
    """A frame whose axes point along the given (orthonormal, right-handed) directions."""
    rotation = np.array([x_axis, y_axis, z_axis], dtype=float).T
    if not np.allclose(rotation.T @ rotation, np.eye(3), atol=1e-9) or np.linalg.det(rotation) < 0:
        raise ValueError("frame axes must be orthonormal and right-handed")
    return Frame(rotation, np.array(position, dtype=float))


IDENTITY = Frame(np.eye(3), np.zeros(3))
