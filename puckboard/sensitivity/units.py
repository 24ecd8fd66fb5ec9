"""Values as people read them: lengths in mm, angles in degrees (``--json`` keeps SI).

Both methods' tables and figures show a profile's numbers this way.
"""

from __future__ import annotations

import math

__all__ = ["describe_value", "shown_scale"]


def describe_value(value: float, unit: str) -> str:
    """A value as people read it: mm for lengths, degrees for angles."""
    if unit == "m":
        return f"{value * 1000:.4g} mm"
    if unit == "rad":
        return f"{math.degrees(value):.4g}°"
    return f"{value:.4g}"


def shown_scale(unit: str) -> tuple[float, str]:
    """Factor and unit that tables and plots show a field's values in."""
    if unit == "m":
        return 1000.0, "mm"
    if unit == "rad":
        return math.degrees(1.0), "°"
    return 1.0, "" if unit == "1" else unit
