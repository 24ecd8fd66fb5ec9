"""Drive to a point of the odometry frame, for as long as the estimate is good enough.

The first layer in puckboard that acts on *derived* knowledge rather than on a raw
sensor: it reads ``estimate/pose`` and ``estimate/pose_cov``, which an
:class:`~puckboard.estimation.OdometrySource` writes (a knowledge source attached to
the loop). The odometry frame starts where the robot started, so the default target,
the origin, is "home".

It applies once ``after`` seconds have passed (or at once, with ``after=0``) and
steers with a proportional heading controller: turn towards the target, slowing the
forward speed as the heading error grows so the robot turns on the spot when the
target is behind it. Within ``tolerance`` of the target it stops and stays stopped.

Because the estimate carries its uncertainty, the layer can be honest about it: when
the position's standard deviation (√ of the trace of the x, y covariance) exceeds
``max_sd``, the estimate is no longer worth steering by and the layer stops applying,
so the layers below it (line following, wandering) take over again instead of driving
confidently to the wrong place. A layer above it (obstacle avoidance) still suppresses
it as any subsumption layer would.
"""

from __future__ import annotations

import math

from ..records import Pose, WheelCommand
from .cruise import DEFAULT_SPEED
from .layer import Frame, Layer

__all__ = ["GoHome"]


class GoHome(Layer):
    """Go to ``home`` (x, y in m, odometry frame) after ``after`` s; see the module docstring.

    ``speed`` (rad/s) is the forward wheel speed, ``gain`` the turn (rad/s of wheel speed
    difference per rad of heading error), ``tolerance`` (m) the arrival radius,
    ``max_sd`` (m) the uncertainty beyond which the layer gives up (``inf``: never).
    """

    reads = ("estimate/pose", "estimate/pose_cov")

    def __init__(
        self,
        home: tuple[float, float] = (0.0, 0.0),
        *,
        after: float = 0.0,
        speed: float = DEFAULT_SPEED,
        gain: float = 4.0,
        tolerance: float = 0.02,
        max_sd: float = math.inf,
        name: str | None = None,
    ) -> None:
        super().__init__(name)
        if tolerance <= 0:
            raise ValueError(f"GoHome tolerance must be positive metres, got {tolerance}")
        if speed <= 0:
            raise ValueError(f"GoHome speed must be positive rad/s, got {speed}")
        self.home_x, self.home_y = (float(v) for v in home)
        self.after = after
        self.speed = speed
        self.gain = gain
        self.tolerance = tolerance
        self.max_sd = max_sd
        self.arrived = False

    def reset(self) -> None:
        """A new start: not home yet."""
        self.arrived = False

    def position_sd(self, frame: Frame) -> float | None:
        """√(σx² + σy²) of the current estimate (m), or ``None`` without a covariance."""
        cov = frame.value("estimate/pose_cov")
        if cov is None:
            return None
        return math.sqrt(max(float(cov[0][0]) + float(cov[1][1]), 0.0))

    def applies(self, frame: Frame) -> bool:
        pose = frame.value("estimate/pose")
        if not isinstance(pose, Pose) or frame.time < self.after:
            return False
        sd = self.position_sd(frame)
        return not (sd is not None and sd > self.max_sd)

    def command(self, frame: Frame) -> WheelCommand:
        pose: Pose = frame.value("estimate/pose")
        dx, dy = self.home_x - pose.x, self.home_y - pose.y
        if self.arrived or math.hypot(dx, dy) <= self.tolerance:
            self.arrived = True
            return WheelCommand.stop()
        error = math.remainder(math.atan2(dy, dx) - pose.theta, math.tau)
        forward = self.speed * max(0.0, math.cos(error))  # no forward drive while facing away
        turn = max(-self.speed, min(self.speed, self.gain * error))
        return WheelCommand(forward - turn, forward + turn)
