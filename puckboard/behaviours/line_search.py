"""Line search with a memory: curve towards the side on which the line was last seen.

Off the line with nothing else to do, a robot that drives straight on may leave the
line for good; one that always curves the same way (the tutorial's
``FindLineOnTheRight``) finds it again only when the line happens to be on that side.
Where the line is, the ground sensors said a moment ago: the outer sensor that saw it
last is on the side the line went. :class:`LineSearch` keeps that in ``observe``, which
runs on every layer at every tick, so the memory stays current while avoidance or line
following drive and this layer is suppressed.

It applies while no ground sensor sees the line, and curves towards the remembered
side: the outer wheel at ``speed``, the inner at ``ratio * speed``. Before it has seen
the line at all it curves towards ``default_side``, and so again after
:meth:`~puckboard.behaviours.Controller.reset` (its :meth:`reset` forgets the side).

A robot put down by hand may not see the line at its first tick (a centimetre off, turned
away from it): curving towards ``default_side`` then goes round a whole circle beside a
line that lies on the other side, and whatever turns it on the way (the other robot, met
head-on) lets it find the line at an angle that sends it back the way it came
(``turned_back``, ``--variation reality-gap``; docs/controllers.md, "Beyond the design
model"). With ``sweep`` (s) above 0, until any ground sensor has seen the line the search
first turns on the spot: towards ``default_side`` for ``sweep`` seconds, the other way for
twice that, and back for ``sweep`` seconds to the heading it started from. The sensor bar,
ahead of the wheels, sweeps both sides of where the robot stands (at the shipped speed
and 0.5 s, about 45° each way: 2 cm either side, 3 cm ahead) and meets a line beside it at
an angle it follows onwards. Then, or once the line has been seen, the search is the
curve above, from the heading the robot was put down with: a scene without a line (the
``arena``) loses the sweep's 4 × ``sweep`` seconds and nothing else. 0 (the default)
never sweeps.

"Off the line" must mean what the line-following layer means by it: were their two
thresholds different, a band of readings would be dark to one and light to the other,
and there neither would drive (another layer would) or both would want to. Given the
line-following layer (``line=``), the search reads that layer's ``threshold`` and has
none of its own to tune: one number for both.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ..records import WheelCommand
from .cruise import DEFAULT_SPEED
from .layer import Frame, Layer

if TYPE_CHECKING:
    from .line_follow import LineFollow

__all__ = ["LineSearch"]


class LineSearch(Layer):
    """Applies while no ground sensor reads below ``threshold``; curves towards the side
    (``"left"`` or ``"right"``) whose outer sensor saw the line last.

    Parameters: ``speed`` (rad/s of the outer wheel), ``ratio`` (inner wheel's fraction
    of ``speed``; 1 drives straight), ``threshold`` (dark below it, as
    :class:`~puckboard.behaviours.LineFollow`), ``default_side``; ``sweep`` (s, the
    first swing of the turns on the spot before the line was first seen; 0: none); ``line``, the
    :class:`~puckboard.behaviours.LineFollow` whose ``threshold`` this search shares
    (then ``threshold`` is that layer's, and setting either sets both).
    """

    reads = ("ground",)

    def __init__(
        self,
        speed: float = DEFAULT_SPEED,
        *,
        ratio: float = 0.8,
        threshold: float = 0.5,
        default_side: str = "right",
        sweep: float = 0.0,
        line: LineFollow | None = None,
        name: str | None = None,
    ) -> None:
        super().__init__(name)
        if default_side not in ("left", "right"):
            raise ValueError(f"default_side must be 'left' or 'right', got {default_side!r}")
        self.speed = speed
        self.ratio = ratio
        self.line = line
        self._threshold = threshold
        self.default_side = default_side
        self.sweep = sweep
        self._last_side: str | None = None
        self._seen = False  # has any ground sensor seen the line since the start?
        self._sweep_start: float | None = None

    @property
    def threshold(self) -> float:
        """Dark below it: the shared line-following layer's, when there is one."""
        return self._threshold if self.line is None else self.line.threshold

    @threshold.setter
    def threshold(self, value: float) -> None:
        if self.line is None:
            self._threshold = value
        else:
            self.line.threshold = value

    def parameters(self) -> dict[str, Any]:
        """As every layer's, with ``threshold`` only where it is this layer's own number
        (a shared one is tuned on the line-following layer)."""
        out = super().parameters()
        if self.line is None:
            out["threshold"] = self._threshold
        return out

    @property
    def last_side(self) -> str:
        """The side the line was last seen on (``default_side`` before it was seen)."""
        return self._last_side or self.default_side

    def reset(self) -> None:
        """A new start: the line has not been seen yet (curve towards ``default_side``)."""
        self._last_side = None
        self._seen = False
        self._sweep_start = None

    def _dark(self, values: list[float]) -> tuple[bool, bool, bool]:
        """Which of (left, centre, right) read the line: as the shared line-following
        layer decides (its thresholds, learned or not), else below ``threshold``."""
        if self.line is not None:
            return self.line.dark(values)
        t = self._threshold
        return values[0] < t, values[1] < t, values[2] < t

    def observe(self, frame: Frame) -> None:
        ground = frame.ground
        if ground is None:
            return
        left_dark, centre_dark, right_dark = self._dark(ground.value.tolist())
        if not self._seen and (left_dark or centre_dark or right_dark):
            self._seen = True
        if left_dark != right_dark:  # one outer sensor alone: the line is on its side
            self._last_side = "left" if left_dark else "right"

    def applies(self, frame: Frame) -> bool:
        ground = frame.ground
        return ground is not None and not any(self._dark(ground.value.tolist()))

    def command(self, frame: Frame) -> WheelCommand:
        if self.sweep > 0.0 and not self._seen:
            sweep = self._sweep_command(frame.time)
            if sweep is not None:
                return sweep
        outer, inner = self.speed, self.ratio * self.speed
        return (
            WheelCommand(outer, inner) if self.last_side == "right" else WheelCommand(inner, outer)
        )

    def _sweep_command(self, now: float) -> WheelCommand | None:
        """Turn on the spot: towards ``default_side`` for ``sweep`` s, the other way for
        twice that, back for ``sweep`` s; None after those ``4 * sweep`` seconds."""
        if self._sweep_start is None:
            self._sweep_start = now
        elapsed = (now - self._sweep_start) / self.sweep
        if elapsed >= 4.0:
            return None
        towards_default = elapsed < 1.0 or elapsed >= 3.0
        right = (self.default_side == "right") == towards_default
        v = self.speed
        return WheelCommand(v, -v) if right else WheelCommand(-v, v)
