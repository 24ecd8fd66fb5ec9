"""Front-obstacle avoidance: the stock Braitenberg 'fear' and the thesis's left-turn fix.

Both layers apply when any of the four front sensors (diagonal_left, front_left,
front_right, diagonal_right: V-REP's sensors 2-5) sees something within range.

:class:`FrontBraitenbergAvoid` is the stock V-REP behaviour (Code 4.13, lines 34-40):
each front sensor speeds up the wheel on its own side and slows the other, weights
``(1, 2, -2, -1)`` from left to right, scaled by closeness ``1 - d/range``. The robot turns
*away* from whatever it sees. Two such robots meeting slightly off-centre can each turn
away from their own side and, seen from above, both veer the same way: in the thesis's
V-REP runs they ended up driving side by side (its Figure 4.6). Met nearly head-on, the
left and right terms cancel and the robots drive into each other, as they do in the
embedded ``two-robot-pass`` scene; facing a flat wall, a robot pushes into it.

:class:`FrontObstacleLeftTurn` is the improved controller's fix (Code 4.14, lines 28-39):
the *first* reaction is always a left turn on the spot-ish (right wheel forward at full
speed, left wheel backwards at half speed), so the obstacle always ends up on the robot's
right. Two robots meeting head-on both turn to their own left and pass each other right
side to right side. Only when both front sensors are very close (within a quarter of the
range) does it fall back to the Braitenberg reflex.

Ambiguity resolved (recorded in docs/controllers.md): the thesis's prose says "if an
obstacle is detected by one of the two front sensors the robot turns left", but its code
tests ``proxSensDist[2] > 0.25*range || proxSensDist[3] > 0.25*range``, which is also true
when those sensors see nothing (they then read ``range``). We port the code, not the
prose: it is what was run to produce the thesis's result.
"""

from __future__ import annotations

from operator import itemgetter

from ..records import PROX_NAMES, Proximity, WheelCommand
from .cruise import DEFAULT_SPEED
from .layer import Frame, Layer

__all__ = ["FRONT_SENSORS", "FrontBraitenbergAvoid", "FrontObstacleLeftTurn", "obstacle_in_front"]

FRONT_SENSORS = ("diagonal_left", "front_left", "front_right", "diagonal_right")
"""The four front sensors, left to right (V-REP's ePuck_proxSensor2..5)."""

_FRONT_IDX = [PROX_NAMES.index(n) for n in FRONT_SENSORS]
_front_distances = itemgetter(*_FRONT_IDX)
_BRAITENBERG_FRONT = (1.0, 2.0, -2.0, -1.0)


def obstacle_in_front(prox: Proximity) -> bool:
    """True when any of the four front sensors sees something within range."""
    # plain floats: cheaper than ufuncs or numpy scalars; "any sensor sees something" is
    # "the nearest reading is within range"
    return min(_front_distances(prox.distance.tolist())) < prox.range


def braitenberg_front(prox: Proximity, speed: float, weights=_BRAITENBERG_FRONT) -> WheelCommand:  # type: ignore[no-untyped-def]
    """The V-REP script's front Braitenberg: start at ``speed`` on both wheels and add
    ``speed * w * (1 - d/range)`` per front sensor, mirrored for the right wheel."""
    closeness = 1.0 - prox.distance[_FRONT_IDX] / prox.range
    left = speed
    right = speed
    n = len(weights)
    for i in range(n):
        left += speed * weights[i] * closeness[i]
        right += speed * weights[n - 1 - i] * closeness[i]
    return WheelCommand(float(left), float(right))


class FrontBraitenbergAvoid(Layer):
    """The stock 'fear' avoidance; applies while something is in front."""

    reads = ("proximity",)

    def __init__(self, speed: float = DEFAULT_SPEED, name: str | None = None) -> None:
        super().__init__(name)
        self.speed = speed

    def applies(self, frame: Frame) -> bool:
        prox = frame.proximity
        return prox is not None and obstacle_in_front(prox)

    def command(self, frame: Frame) -> WheelCommand:
        prox = frame.proximity
        assert prox is not None
        return braitenberg_front(prox, self.speed)


class FrontObstacleLeftTurn(FrontBraitenbergAvoid):
    """Always turn left first, so the obstacle stays on the right; see the module docstring.

    ``turn_speed`` is the right wheel's speed during the turn (the left wheel runs at
    ``-reverse_factor * turn_speed``: ``reverse_factor`` 0.5, the thesis's half speed,
    carries the robot forward while it turns; 1 turns on the spot); ``close_fraction``
    is the fraction of the range below which both front sensors must be to fall back
    to Braitenberg; ``braitenberg_fallback=False`` never falls back: the turn is
    always left (the ``robust`` controller's choice).
    """

    def __init__(
        self,
        speed: float = DEFAULT_SPEED,
        *,
        turn_speed: float | None = None,
        close_fraction: float = 0.25,
        braitenberg_fallback: bool = True,
        reverse_factor: float = 0.5,
        name: str | None = None,
    ) -> None:
        super().__init__(speed, name)
        self.turn_speed = speed if turn_speed is None else turn_speed
        self.reverse_factor = reverse_factor
        self.close_fraction = close_fraction
        self.braitenberg_fallback = braitenberg_fallback

    def command(self, frame: Frame) -> WheelCommand:
        prox = frame.proximity
        assert prox is not None
        turn = WheelCommand(-self.reverse_factor * self.turn_speed, self.turn_speed)
        if not self.braitenberg_fallback:
            return turn
        limit = self.close_fraction * prox.range
        if prox.front_left > limit or prox.front_right > limit:
            return turn
        return braitenberg_front(prox, self.speed)
