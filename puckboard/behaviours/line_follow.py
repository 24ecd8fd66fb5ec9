"""Line following on the three ground sensors.

A light floor reads near 1, the dark line below ``threshold`` (0.5, as in V-REP's model).
The stock V-REP script slows the wheel on the side whose sensor sees the line, so the
robot turns back onto it (Code 4.13, lines 7-17). The improved controller (Code 4.14,
lines 3-19) adds three recovery cases that make *finding* the line again reliable after
an avoidance manoeuvre, when the robot meets the line at an angle:

* centre and right sensors dark, left light: a sharp right turn (right wheel reverses);
* centre and left dark, right light: a sharp left turn;
* all three dark (crossing the line at a right angle): spin left on the spot.

``recovery=True`` selects the improved behaviour.
"""

from __future__ import annotations

from ..records import WheelCommand
from .cruise import DEFAULT_SPEED
from .layer import Frame, Layer

__all__ = ["LineFollow"]


class LineFollow(Layer):
    """Follow a dark line; applies while a fresh ground reading sees the line.

    Parameters: ``speed`` (rad/s), ``inner_factor`` (fraction of ``speed`` for the wheel
    on the line's side: 0.25 stock, 0.20 improved), ``threshold`` (dark below it),
    ``recovery`` and ``sharp_factor`` (the improved controller's reversing turns).
    """

    reads = ("ground",)

    def __init__(
        self,
        speed: float = DEFAULT_SPEED,
        *,
        inner_factor: float = 0.25,
        threshold: float = 0.5,
        recovery: bool = False,
        sharp_factor: float = 0.75,
        name: str | None = None,
    ) -> None:
        super().__init__(name)
        self.speed = speed
        self.inner_factor = inner_factor
        self.threshold = threshold
        self.recovery = recovery
        self.sharp_factor = sharp_factor

    # Both tests compare the three readings as plain floats: the same comparisons as
    # ``Ground.dark``, without the numpy calls or a generator, on a layer the arbiter
    # asks every tick ("some sensor is dark" is "the darkest sensor is dark").
    def applies(self, frame: Frame) -> bool:
        ground = frame.ground
        if ground is None:
            return False
        return min(ground.value.tolist()) < self.threshold

    def command(self, frame: Frame) -> WheelCommand:
        ground = frame.ground
        assert ground is not None
        threshold = self.threshold
        left, centre, right = ground.value.tolist()
        left_dark, centre_dark, right_dark = left < threshold, centre < threshold, right < threshold
        v = self.speed
        if self.recovery:
            if centre_dark and right_dark and not left_dark:
                return WheelCommand(v, -self.sharp_factor * v)
            if centre_dark and left_dark and not right_dark:
                return WheelCommand(-self.sharp_factor * v, v)
            if left_dark and centre_dark and right_dark:
                return WheelCommand(-v, v)
        left = self.inner_factor * v if left_dark else v
        right = self.inner_factor * v if right_dark else v
        return WheelCommand(left, right)
