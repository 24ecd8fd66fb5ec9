"""Sensor records and a settable clock for testing layers on hand-set readings.

The behaviour tests feed layers proximity and ground records they build themselves, so a
layer's decision can be checked against the source's pseudo-code on exact values.
"""

from __future__ import annotations

import math

import numpy as np

from puckboard.records import PROX_NAMES, Ground, Proximity

#: The V-REP script's maxVel (rad/s), every preset's speed.
MAX = math.radians(120)


class Clock:
    """A blackboard clock the test sets by hand (``clock.t = 1.5``)."""

    t = 0.0

    def __call__(self) -> float:
        return self.t


def prox(**distances: float) -> Proximity:
    """Proximity with every sensor at 5 cm except the named ones (metres)."""
    arr = np.full(8, 0.05)
    for name, value in distances.items():
        arr[PROX_NAMES.index(name)] = value
    return Proximity(arr, np.zeros(8))


def ground(left: float = 1.0, centre: float = 1.0, right: float = 1.0) -> Ground:
    """Ground readings (0 dark, 1 light) and their raw values."""
    v = np.array([left, centre, right])
    return Ground(v, v * 1023)
