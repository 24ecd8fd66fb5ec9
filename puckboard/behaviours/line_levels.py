"""Line levels learned from the tape the robot is on: a threshold per ground sensor.

A fixed threshold (0.5, V-REP's script's) assumes black tape reads near 0 and the floor
near 1. A real e-puck2 reads black tape at 0.30-0.42 of white, each of its three sensors
at its own level, about 100 counts apart (a real robot's recording, docs/profiles.md);
worn or glossy tape reads lighter still. Such a line can read above 0.5 on every sensor:
to a fixed threshold it is not there.

Thymio's edge follower keeps a running minimum and maximum of its ground sensor and puts
its threshold in their middle; the e-puck library's calibration samples the black line
and the white floor before a run. :class:`LineLevels` does the first with the three
sensors together: the floor is the same floor under all three (their lightest readings
agree within a few hundredths), and the line is the darkest any of them has read (each
reading averaged with the two before it, so that one noisy reading does not set a level).
One threshold in their middle serves all three: a sensor's own extremes would not do, since
an outer sensor that has only brushed the tape's edge has a shallow minimum, and a
threshold in its middle would read the floor's noise as line. Until the two levels are
``min_contrast`` apart (no sensor has crossed the line yet), the fixed ``threshold``
holds.

A reading that repeats the last one exactly (the link brought no new packet) teaches
nothing and is skipped.
"""

from __future__ import annotations

__all__ = ["LineLevels"]


class LineLevels:
    """Each ground sensor's darkest and lightest reading so far, and its threshold."""

    def __init__(self, threshold: float = 0.5, *, min_contrast: float = 0.2) -> None:
        self.threshold = threshold
        self.min_contrast = min_contrast
        self.reset()

    def reset(self) -> None:
        """Forget what was learned (a new start, on another table)."""
        self.low: list[float | None] = [None, None, None]
        self.high: list[float | None] = [None, None, None]
        self._recent: list[tuple[float, float, float]] = []

    def learn(self, values: tuple[float, float, float] | list[float]) -> None:
        """Take one reading (left, centre, right) into the levels."""
        reading = (float(values[0]), float(values[1]), float(values[2]))
        if self._recent and reading == self._recent[-1]:
            return  # the same packet again
        self._recent = [*self._recent[-2:], reading]
        if len(self._recent) < 3:
            return
        for k in range(3):
            mean = (self._recent[0][k] + self._recent[1][k] + self._recent[2][k]) / 3.0
            low, high = self.low[k], self.high[k]
            self.low[k] = mean if low is None or mean < low else low
            self.high[k] = mean if high is None or mean > high else high

    def smoothed(self, values: list[float]) -> list[float]:
        """``values`` averaged with the reading before, once both are learned: the floor's
        noise, which a faint line's half-contrast may not clear, halves in variance."""
        recent = self._recent
        if len(recent) < 2 or tuple(float(v) for v in values) != recent[-1]:
            return list(values)
        a, b = recent[-2], recent[-1]
        return [0.5 * (a[k] + b[k]) for k in range(3)]

    def levels(self) -> tuple[float, float] | None:
        """(line, floor): the darkest smoothed reading of any sensor and the middle one of
        the three sensors' lightest; None before three readings."""
        if self.low[0] is None:
            return None
        lows = [v for v in self.low if v is not None]
        highs = sorted(v for v in self.high if v is not None)
        return min(lows), highs[len(highs) // 2]

    def thresholds(self) -> tuple[float, float, float]:
        """The threshold of each sensor: the middle of the line's and the floor's levels
        once they are ``min_contrast`` apart, else the fixed one."""
        levels = self.levels()
        if levels is None or levels[1] - levels[0] < self.min_contrast:
            t = self.threshold
        else:
            t = 0.5 * (levels[0] + levels[1])
        return t, t, t
