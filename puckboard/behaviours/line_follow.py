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

Two options answer a real table (``robust``; docs/controllers.md):

* ``learn=True``: each sensor's threshold is learned from the tape the robot is on
  (:class:`~.line_levels.LineLevels`, in :meth:`observe`, every tick), where a real
  e-puck2 reads black tape at 0.30-0.42 of white and worn tape lighter still;
* ``settle`` (s) above 0: the recovery turns act only within ``settle`` seconds of
  meeting the line. Tape as wide as the outer sensors' spread (¾ inch, 19 mm, against
  20 mm) darkens the centre and an outer sensor, or all three, while the robot rides
  it straight: the same readings as meeting the line at an angle, or crossing it. Once
  the robot has followed the line for ``settle`` seconds they mean a wide line, so the
  robot then steers gently towards the dark side (the inner wheel at ``inner_factor``)
  or, all three dark, drives straight on.
"""

from __future__ import annotations

from typing import Any

from ..records import WheelCommand
from .cruise import DEFAULT_SPEED
from .layer import Frame, Layer
from .line_levels import LineLevels

__all__ = ["LineFollow"]


class LineFollow(Layer):
    """Follow a dark line; applies while a fresh ground reading sees the line.

    Parameters: ``speed`` (rad/s), ``inner_factor`` (fraction of ``speed`` for the wheel
    on the line's side: 0.25 stock, 0.20 improved), ``threshold`` (dark below it),
    ``recovery`` and ``sharp_factor`` (the improved controller's reversing turns);
    ``learn`` (each sensor's threshold learned from the tape; ``threshold`` until then)
    and ``settle`` (s; the recovery turns only within that long of meeting the line; 0:
    always), see the module docstring.
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
        learn: bool = False,
        settle: float = 0.0,
        name: str | None = None,
    ) -> None:
        super().__init__(name)
        self.speed = speed
        self.inner_factor = inner_factor
        self._levels = LineLevels(threshold) if learn else None
        self._threshold = threshold
        self.recovery = recovery
        self.sharp_factor = sharp_factor
        self.settle = settle
        self._met_at: float | None = None  # when the line was last met (None: off it)

    @property
    def threshold(self) -> float:
        """Dark below it (until learned, with ``learn``)."""
        return self._threshold

    @threshold.setter
    def threshold(self, value: float) -> None:
        self._threshold = value
        if self._levels is not None:
            self._levels.threshold = value

    @property
    def learn(self) -> bool:
        """Whether each sensor's threshold is learned from the tape."""
        return self._levels is not None

    @learn.setter
    def learn(self, value: bool) -> None:
        if bool(value) != self.learn:
            self._levels = LineLevels(self._threshold) if value else None

    def parameters(self) -> dict[str, Any]:
        """As every layer's, with ``threshold`` and ``learn`` (properties: setting the
        threshold sets the learned levels' fallback too)."""
        out: dict[str, Any] = {"speed": self.speed, "inner_factor": self.inner_factor}
        out.update(threshold=self._threshold, recovery=self.recovery)
        out.update(sharp_factor=self.sharp_factor, learn=self.learn, settle=self.settle)
        return {k: v for k, v in out.items() if isinstance(v, (int, float, str, bool, tuple))}

    def dark(self, values: list[float]) -> tuple[bool, bool, bool]:
        """Which of (left, centre, right) read the line."""
        left, centre, right = values
        if self._levels is None:
            t = self._threshold
            return left < t, centre < t, right < t
        tl, tc, tr = self._levels.thresholds()
        left, centre, right = self._levels.smoothed(values)
        return left < tl, centre < tc, right < tr

    def reset(self) -> None:
        """A new start: nothing learned, not on the line."""
        if self._levels is not None:
            self._levels.reset()
        self._met_at = None

    def observe(self, frame: Frame) -> None:
        if self._levels is None and not self.settle:
            return
        ground = frame.ground
        if ground is None:
            return
        values = ground.value.tolist()
        if self._levels is not None:
            self._levels.learn(values)
        if any(self.dark(values)):
            if self._met_at is None:
                self._met_at = frame.time
        else:
            self._met_at = None

    # Both tests compare the three readings as plain floats: the same comparisons as
    # ``Ground.dark``, without the numpy calls or a generator, on a layer the arbiter
    # asks every tick ("some sensor is dark" is "the darkest sensor is dark").
    def applies(self, frame: Frame) -> bool:
        ground = frame.ground
        if ground is None:
            return False
        if self._levels is None:
            return min(ground.value.tolist()) < self._threshold
        return any(self.dark(ground.value.tolist()))

    def command(self, frame: Frame) -> WheelCommand:
        ground = frame.ground
        assert ground is not None
        left_dark, centre_dark, right_dark = self.dark(ground.value.tolist())
        v = self.speed
        settled = (
            self.settle > 0.0
            and self._met_at is not None
            and frame.time - self._met_at >= self.settle
        )
        if self.recovery and settled and centre_dark:
            # riding a wide line: steer gently towards its dark side, or straight on
            if left_dark and right_dark:
                return WheelCommand(v, v)
        elif self.recovery:
            if centre_dark and right_dark and not left_dark:
                return WheelCommand(v, -self.sharp_factor * v)
            if centre_dark and left_dark and not right_dark:
                return WheelCommand(-self.sharp_factor * v, v)
            if left_dark and centre_dark and right_dark:
                return WheelCommand(-v, v)
        left = self.inner_factor * v if left_dark else v
        right = self.inner_factor * v if right_dark else v
        return WheelCommand(left, right)
