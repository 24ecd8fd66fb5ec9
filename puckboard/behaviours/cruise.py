"""Cruise: the lowest layer, always applies, drives straight ahead."""

from __future__ import annotations

import math

from ..records import WheelCommand
from .layer import Frame, Layer

__all__ = ["DEFAULT_SPEED", "Cruise"]

DEFAULT_SPEED = math.radians(120.0)
"""The V-REP e-puck script's ``maxVel``: 120 °/s of wheel rotation (≈ 4.3 cm/s)."""


class Cruise(Layer):
    """Drive straight at ``speed`` (rad/s). At the bottom of a controller it makes sure
    some layer always applies, so the robot never stands still for lack of a reason."""

    def __init__(self, speed: float = DEFAULT_SPEED, name: str | None = None) -> None:
        super().__init__(name)
        self.speed = speed

    def command(self, frame: Frame) -> WheelCommand:
        return WheelCommand(self.speed, self.speed)
