"""The checks that stop a calibration that cannot work, each saying what to fix.

They compare what the robot read with what the simulator's model of its sensors
(:class:`~.response.WallModel`, gain 1) says a robot there would read, and they are
deliberately coarse: a sensor is taken to respond when it answers with at least a tenth
of the model's response (:data:`MIN_RESPONSE`), far below the plausible spread of real
sensors (gains 0.7 to 1.3, docs/profiles.md), and to be saturated when its mean lies
within three spreads of full scale, so that they stop only runs that cannot give a fit,
never a robot that is merely unusual. Each raises
:class:`~puckboard.errors.CalibrationError` with one line.

* :func:`wall_seen`, at the first pose: the front sensors see the wall they touch.
* :func:`sensors_respond`, after the first full turn: every sensor answers the wall when
  presented to it, and none reads full scale with the wall out of its reach.
* :func:`moving_away`, at every later stop: backing away changes what the first presented
  sensor reads (wheels that turn on the spot, or a robot held, would not).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..errors import CalibrationError
from ..ir_response import RAW_MAX
from ..records import PROX_NAMES

if TYPE_CHECKING:
    from .readings import PoseReading
    from .response import WallModel

__all__ = ["MIN_RESPONSE", "moving_away", "sensors_respond", "wall_seen"]

#: The smallest response, as a fraction of the gain-1 model's, that counts as a sensor
#: answering (a gain of 0.1, seven times below the plausible 0.7).
MIN_RESPONSE = 0.1
#: Backing away must bring the front sensors below this fraction of what they read
#: touching, once the model says they should have fallen below half.
STILL_FRACTION = 0.9
#: A mean within this many spreads of full scale is a sensor at full scale.
FULL_SCALE_SPREADS = 3.0

_FRONT = (PROX_NAMES.index("front_right"), PROX_NAMES.index("front_left"))
_SWITCHED_ON_AWAY = (
    "the robot measures its sensors' baselines when it is switched on, so switch it on "
    "with nothing within 10 cm and only then put it against the wall"
)


def _at_full_scale(mean: np.ndarray, std: np.ndarray) -> np.ndarray:
    """Which sensors read full scale: a mean within three spreads of it (the readings of
    a value at full scale are clipped there, so their mean lies just below it)."""
    return np.asarray(mean + FULL_SCALE_SPREADS * np.maximum(std, 1.0) >= RAW_MAX)


def _expected(reading: PoseReading, model: WallModel) -> np.ndarray:
    return model.expected(reading.distance, reading.heading)


def wall_seen(first: PoseReading, model: WallModel) -> None:
    """At the first pose the robot touches the wall, facing it: its front sensors must
    read a good part of what the model expects there, and not every sensor full scale."""
    if np.all(_at_full_scale(first.mean, first.std)):
        raise CalibrationError(
            f"readings saturated: every sensor reads full scale ({RAW_MAX:.0f}) at the start; "
            "something covers the robot's sensors or their calibration is wrong: "
            + _SWITCHED_ON_AWAY
        )
    expected = _expected(first, model)
    seen = [first.mean[i] >= MIN_RESPONSE * expected[i] for i in _FRONT]
    if not any(seen):
        a, b = (first.mean[i] for i in _FRONT)
        raise CalibrationError(
            f"no wall seen: touching the wall and facing it, the front sensors read {a:.0f} "
            f"and {b:.0f} where a white wall gives about {expected[_FRONT[0]]:.0f}; place the "
            "robot touching a white wall, facing it, and start again (and "
            f"{_SWITCHED_ON_AWAY})"
        )


def sensors_respond(readings: Sequence[PoseReading], model: WallModel) -> None:
    """After the first full turn (every sensor presented once, touching the wall): each
    sensor must answer the wall and must not read full scale when turned away from it."""
    expected = np.array([_expected(r, model) for r in readings])
    means = np.array([r.mean for r in readings])
    full = np.array([_at_full_scale(r.mean, r.std) for r in readings])
    problems = []
    for i, name in enumerate(PROX_NAMES):
        far = expected[:, i] <= 0.0
        if far.any() and np.all(full[far, i]):
            problems.append(
                f"sensor {name} reads full scale ({RAW_MAX:.0f}) even turned away from the "
                "wall: something is right in front of it, or it is faulty"
            )
            continue
        best = int(np.argmax(expected[:, i]))
        baseline = float(np.median(means[far, i])) if far.any() else 0.0
        answer = means[best, i] - baseline
        if answer < MIN_RESPONSE * expected[best, i]:
            problems.append(
                f"sensor {name} does not respond: it reads {means[best, i]:.0f} presented to "
                f"the wall and {baseline:.0f} turned away, where a typical sensor reads "
                f"about {expected[best, i]:.0f} more; check it is clean and uncovered"
            )
    if problems:
        hint = "" if all("full scale" in p for p in problems) else f" ({_SWITCHED_ON_AWAY})"
        raise CalibrationError("; ".join(problems) + hint)


def moving_away(first: PoseReading, now: PoseReading, model: WallModel) -> None:
    """Backing away must show: once the model says the presented sensors' response should
    have halved since the first stop (touching the wall), they must read clearly less."""
    sensors = [PROX_NAMES.index(name) for name in now.sensors]
    expected_first = sum(_expected(first, model)[i] for i in sensors)
    expected_now = sum(_expected(now, model)[i] for i in sensors)
    if expected_first <= 0 or expected_now / expected_first >= 0.5:
        return
    touching = sum(first.mean[i] for i in sensors)
    read = sum(now.mean[i] for i in sensors)
    if touching > 0 and read / touching > STILL_FRACTION:
        names = " and ".join(now.sensors)
        raise CalibrationError(
            f"the robot does not move away from the wall: {now.backed * 1000:.0f} mm back by "
            f"its step counters, {names} reads {read:.0f}, as touching ({touching:.0f}); "
            "something holds it or its wheels slip: use a flat, hard floor with nothing "
            "behind the robot"
        )
