"""Side wall keeping, Braitenberg style, on the left and/or right side sensor.

From the V-REP script (Code 4.13 lines 21-33; the improved controller keeps only the
right side, Code 4.14 lines 21-27). While a side sensor sees something between a quarter
of the range and the range, the wheel on that side is slowed by
``speed * (1 - d/range)``: the robot curves *towards* the obstacle, more the closer it
is, until the obstacle leaves the front sensors' view and the obstacle-avoidance layer
takes over again. The two together make the robot trace the contour of an obstacle at a
roughly constant distance. Closer than a quarter of the range the correction stops and
the robot drives straight, which lets it peel away.
"""

from __future__ import annotations

from ..records import PROX_NAMES, WheelCommand
from .cruise import DEFAULT_SPEED
from .layer import Frame, Layer

__all__ = ["SideWallKeep"]

_BRAITENBERG_SIDE = (-1.0, 0.0)  # (own-side wheel, other wheel), the script's braitSideSens
# the side sensors' indices: a tick reads plain floats instead of looking names up on the record
_SIDE_INDEX = {side: PROX_NAMES.index(side) for side in ("left", "right")}


class SideWallKeep(Layer):
    """Keep a side obstacle at a distance; ``sides`` is ``("left",)``, ``("right",)`` or both.

    Applies while a chosen side sensor reads between ``near_fraction * range`` and the range.
    """

    reads = ("proximity",)

    def __init__(
        self,
        sides: tuple[str, ...] = ("left", "right"),
        *,
        speed: float = DEFAULT_SPEED,
        near_fraction: float = 0.25,
        weights: tuple[float, float] = _BRAITENBERG_SIDE,
        name: str | None = None,
    ) -> None:
        super().__init__(name)
        bad = [s for s in sides if s not in ("left", "right")]
        if bad or not sides:
            raise ValueError(f"sides must be 'left' and/or 'right', got {sides!r}")
        self.sides = tuple(sides)
        self.speed = speed
        self.near_fraction = near_fraction
        self.weights = tuple(weights)

    def _active_sides(self, frame: Frame) -> list[tuple[str, float]]:
        prox = frame.proximity
        if prox is None:
            return []
        reach = prox.range
        low = self.near_fraction * reach
        distance = prox.distance.tolist()
        out = []
        for side in self.sides:
            d = distance[_SIDE_INDEX[side]]
            if low < d < reach:
                out.append((side, 1.0 - d / reach))
        return out

    def applies(self, frame: Frame) -> bool:
        return bool(self._active_sides(frame))

    def command(self, frame: Frame) -> WheelCommand:
        left = right = self.speed
        own, other = self.weights
        for side, closeness in self._active_sides(frame):
            if side == "left":
                left += self.speed * own * closeness
                right += self.speed * other * closeness
            else:
                left += self.speed * other * closeness
                right += self.speed * own * closeness
        return WheelCommand(left, right)
