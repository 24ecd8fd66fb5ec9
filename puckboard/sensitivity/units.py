"""Values as people read them: lengths in mm, angles in degrees (``--json`` keeps SI).

Both methods' tables and figures show a profile's numbers this way.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

__all__ = ["describe_value", "shown_scale", "value_digits"]

#: Significant digits a value is shown with, unless its neighbours need more.
DIGITS = 4


def describe_value(value: float, unit: str, digits: int = DIGITS) -> str:
    """A value as people read it: mm for lengths, degrees for angles (``digits``
    significant digits)."""
    if unit == "m":
        return f"{value * 1000:.{digits}g} mm"
    if unit == "rad":
        return f"{math.degrees(value):.{digits}g}°"
    return f"{value:.{digits}g}"


def value_digits(values: Sequence[float]) -> int:
    """Significant digits that tell ``values`` apart (at least :data:`DIGITS`): values
    close together (many of them across a narrow range) must not read alike."""
    distinct = len(set(values))
    for digits in range(DIGITS, 16):
        if len({f"{v:.{digits}g}" for v in values}) == distinct:
            return digits
    return 16


def shown_scale(unit: str) -> tuple[float, str]:
    """Factor and unit that tables and plots show a field's values in."""
    if unit == "m":
        return 1000.0, "mm"
    if unit == "rad":
        return math.degrees(1.0), "°"
    return 1.0, "" if unit == "1" else unit
