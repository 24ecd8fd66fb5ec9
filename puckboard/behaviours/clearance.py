"""A clearance guard: never curve towards an obstacle that is already close on one side.

A robot that goes round an obstacle keeps it on one side (the right, after a left-first
avoidance) and curves back towards it to find the line again. Two things in the
controller curve towards that side: the wall-keeping reflex, which stops correcting
inside a quarter of the range so that the robot can peel away, and the line search
below it, which curves towards where the line was. On the physical e-puck the side
sensors sit between wide gaps (front ±17°, diagonal ±46°, side 90°, rear ±151°) and see
a 6 cm cylinder only over a few centimetres, so the layers below the reflex may curve
into a cylinder that the side sensor reports 5-8 mm away: the robot grazes it and the
judge counts a collision (``two-robot-pass``, plausible physical robots).

:class:`ClearanceGuard` answers that: while any of its ``sensors`` reads closer than
``clearance`` (a fraction of the range), it takes the wheels and drives on, turning
*away* from that side by ``away_factor`` (the near-side wheel runs at full ``speed``,
the far-side wheel at ``away_factor * speed``; 1 drives straight). It never turns
towards the obstacle, whatever the layers below would have done, and lets go as soon
as the obstacle is out of that near band, so line following and line search resume.

``side`` can be changed after construction (``--set layer.ClearanceGuard.side=left``):
the watched sensors follow it, each mirrored to the new side, so a guard never watches
one side while it turns away from the other.
"""

from __future__ import annotations

from typing import Any

from ..records import PROX_NAMES, WheelCommand
from .cruise import DEFAULT_SPEED
from .layer import Frame, Layer

__all__ = ["SIDE_SENSORS", "ClearanceGuard"]

SIDE_SENSORS: dict[str, tuple[str, ...]] = {
    "right": ("diagonal_right", "right", "rear_right"),
    "left": ("diagonal_left", "left", "rear_left"),
}
"""The sensors that look to each side, front to back, which a guard watches by default."""


def _mirrored(sensor: str) -> str:
    """The sensor in the mirror position (``diagonal_right`` ↔ ``diagonal_left``)."""
    if "right" in sensor:
        return sensor.replace("right", "left")
    return sensor.replace("left", "right")


class ClearanceGuard(Layer):
    """Applies while an obstacle is within ``clearance * range`` of a ``side`` sensor.

    Parameters: ``side`` (``"right"`` or ``"left"``), ``sensors`` (which of that side's
    sensors to watch; default :data:`SIDE_SENSORS`), ``clearance`` (fraction of the
    proximity range), ``speed`` (rad/s) and ``away_factor`` (the far-side wheel's
    fraction of ``speed``: below 1 turns away from the obstacle).
    """

    reads = ("proximity",)

    def __init__(
        self,
        side: str = "right",
        *,
        sensors: tuple[str, ...] | None = None,
        clearance: float = 0.4,
        speed: float = DEFAULT_SPEED,
        away_factor: float = 0.8,
        name: str | None = None,
    ) -> None:
        super().__init__(name)
        _check_side(side)
        chosen = SIDE_SENSORS[side] if sensors is None else tuple(sensors)
        unknown = [s for s in chosen if s not in PROX_NAMES]
        if unknown or not chosen:
            raise ValueError(
                f"sensors must be proximity sensor names ({', '.join(PROX_NAMES)}), got {chosen!r}"
            )
        self._side = side
        self.sensors = chosen
        self.clearance = clearance
        self.speed = speed
        self.away_factor = away_factor

    @property
    def side(self) -> str:
        """The side watched and turned away from; setting it mirrors the watched sensors."""
        return self._side

    @side.setter
    def side(self, value: str) -> None:
        _check_side(value)
        if value != self._side:
            self.sensors = tuple(_mirrored(s) for s in self.sensors)
        self._side = value

    def parameters(self) -> dict[str, Any]:
        """As every layer's, with ``side`` (a property, so that setting it moves the
        sensors too)."""
        return {**super().parameters(), "side": self._side}

    def applies(self, frame: Frame) -> bool:
        prox = frame.proximity
        if prox is None:
            return False
        distance = prox.distance.tolist()
        limit = self.clearance * prox.range
        return any(distance[PROX_NAMES.index(s)] < limit for s in self.sensors)

    def command(self, frame: Frame) -> WheelCommand:
        near, far = self.speed, self.away_factor * self.speed
        # turning away from the right means the right (near) wheel runs faster
        return WheelCommand(far, near) if self.side == "right" else WheelCommand(near, far)


def _check_side(side: object) -> None:
    if side not in SIDE_SENSORS:
        raise ValueError(f"side must be 'left' or 'right', got {side!r}")
