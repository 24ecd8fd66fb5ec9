"""Differential-drive kinematics with exact arc integration.

The e-puck's stepper motors do not slip in normal use, so the body's motion follows the
wheels exactly (Enki's and Webots' kinematic mode make the same assumption). Within one
step the wheel speeds are constant, so the robot moves along a circular arc; integrating
that arc exactly instead of with an Euler step means a robot told to drive a circle of
radius R draws that circle whatever the time step.

For an arc with forward speed v and turn rate w over dt, the chord has length
``v·dt·sin(h)/h`` (h = w·dt/2) and points along ``theta + h``; ``np.sinc`` gives
``sin(h)/h`` without a special case for straight lines (h = 0).
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

__all__ = ["arc", "arc_step", "body_velocity"]

FloatArray = npt.NDArray[np.float64]


def arc(
    x: float, y: float, theta: float, forward: float, turn: float, dt: float
) -> tuple[float, float, float]:
    """One robot's pose after moving along an exact arc for ``dt`` (plain floats).

    The simulator steps a handful of robots; for so few, scalar maths costs less than
    one numpy call. The returned heading is wrapped to (-π, π].
    """
    half = 0.5 * turn * dt
    chord = forward * dt * (math.sin(half) / half if half != 0.0 else 1.0)
    heading = theta + half
    return (
        x + chord * math.cos(heading),
        y + chord * math.sin(heading),
        math.remainder(theta + 2.0 * half, math.tau),
    )


def body_velocity(
    wheels: FloatArray, wheel_radius: FloatArray, axle: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Wheel speeds (N×2 rad/s, left/right) → forward speed (m/s) and turn rate (rad/s)."""
    left = wheels[:, 0] * wheel_radius
    right = wheels[:, 1] * wheel_radius
    return (left + right) * 0.5, (right - left) / axle


def arc_step(poses: FloatArray, forward: FloatArray, turn: FloatArray, dt: float) -> FloatArray:
    """Displacement (N×3: dx, dy, dtheta) of robots at ``poses`` moving along exact arcs."""
    half = turn * (0.5 * dt)
    chord = forward * dt * np.sinc(half / np.pi)
    heading = poses[:, 2] + half
    out = np.empty_like(poses)
    out[:, 0] = chord * np.cos(heading)
    out[:, 1] = chord * np.sin(heading)
    out[:, 2] = turn * dt
    return out
