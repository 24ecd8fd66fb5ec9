"""Quantities as people write them: a number in SI units, or a number with its unit.

Every place a user gives a quantity reads it here, so ``31mm``, ``17deg`` and ``100ms``
mean the same wherever they are accepted: a profile setting (``--set
profile.prox_radius.side=31mm``), a scene setting (``--set control.period=100ms``), a
calibration's distances (``--distance 60mm``). A bare number is SI (metres, seconds,
radians). Lengths and times convert in decimal, so ``20.3mm`` is exactly the float
nearest 0.0203, as if the user had written ``0.0203``.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from decimal import Decimal

__all__ = ["UNITS", "read_quantity", "unit_words"]


def _decimal(divisor: int) -> Callable[[str], float]:
    return lambda text: float(Decimal(text) / divisor)


def _degrees(text: str) -> float:
    return math.radians(float(text))


#: Each SI unit a quantity is given in, and the units it may be written with instead
#: (the conversion of the written number's text to SI). ``1`` is a plain factor or
#: share, ``raw`` a sensor's raw units: neither takes a unit.
UNITS: dict[str, dict[str, Callable[[str], float]]] = {
    "m": {"m": float, "cm": _decimal(100), "mm": _decimal(1000)},
    "s": {"s": float, "ms": _decimal(1000)},
    "rad": {"rad": float, "deg": _degrees, "°": _degrees},
    "rad/s": {"rad/s": float},
    "1": {},
    "raw": {},
}
_NUMBER_WITH_UNIT = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([a-z°/]*)\s*$")
_WORDS = {
    "m": "metres, or with a unit: 31mm, 3.1cm",
    "s": "seconds, or with a unit: 100ms",
    "rad": "radians, or with a unit: 17deg",
    "1": "a plain factor, no unit",
    "raw": "raw sensor units, no unit",
}


def unit_words(unit: str) -> str:
    """How a quantity of ``unit`` is written, for error messages (``seconds, or with a
    unit: 100ms``)."""
    return _WORDS.get(unit, unit)


def read_quantity(name: str, value: object, unit: str) -> float:
    """``value`` of the quantity ``name`` in SI ``unit``: a number as it is, or a text
    holding a number, with or without one of ``unit``'s written units.

    A ``ValueError`` (one line, naming ``name`` and how to write it) for anything else:
    no number, a unit that does not fit (``5deg`` for a length), or a bool. Whether the
    number is in bounds is the caller's to say.
    """
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise ValueError(f"{name} = {value!r}: expected a number ({unit_words(unit)})")
    if not isinstance(value, str):
        return float(value)
    match = _NUMBER_WITH_UNIT.match(value)
    if match is None:
        raise ValueError(f"{name} = {value!r}: expected a number ({unit_words(unit)})")
    number, suffix = match.group(1), match.group(2)
    if not suffix:
        return float(number)
    written = UNITS.get(unit, {})
    if suffix not in written:
        raise ValueError(f"{name} = {value!r}: unit {suffix!r} does not fit; {unit_words(unit)}")
    return written[suffix](number)
