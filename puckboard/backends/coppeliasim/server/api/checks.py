"""Argument checks: every served call's arguments are checked before anything runs.

A client may send anything (the wrong type, a huge string, ``NaN``); a function of the
dispatch table declares its parameters as :class:`Param` s, and :func:`check_args` turns
what arrived into checked Python values or into CoppeliaSim's own wording of the error
(``bad argument #2 to 'sim.setJointTargetVelocity' (velocity: number expected, got text
string)``), so that no handler ever sees a value it did not ask for.

Each check returns the converted value or raises ``TypeError`` with what was expected.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from .state import ApiError

__all__ = [
    "Handler",
    "Param",
    "anything",
    "boolean",
    "buffer",
    "check_args",
    "int_pair",
    "integer",
    "number",
    "options_map",
    "string",
    "type_name",
    "vector",
]

_REQUIRED = object()


def integer(v: Any) -> int:
    if isinstance(v, bool) or not isinstance(v, int):
        if isinstance(v, float) and v.is_integer() and abs(v) < 2**31:
            return int(v)  # the `cbor` encoder turns some ints into floats
        raise TypeError("integer")
    if abs(v) >= 2**31:
        raise TypeError("integer (32-bit)")
    return v


def number(v: Any) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise TypeError("number")
    f = float(v)
    if not math.isfinite(f):
        raise TypeError("finite number")
    return f


def string(v: Any) -> str:
    if not isinstance(v, str):
        raise TypeError("string")
    if len(v) > 1000:
        raise TypeError("string of at most 1000 characters")
    return v


def buffer(v: Any) -> str | bytes:
    if not isinstance(v, (str, bytes)):
        raise TypeError("string or buffer")
    if len(v) > 65536:
        raise TypeError("string of at most 65536 bytes")
    return v


def boolean(v: Any) -> bool:
    if isinstance(v, bool):
        return v
    if isinstance(v, int) and v in (0, 1):
        return bool(v)
    raise TypeError("boolean")


def anything(v: Any) -> Any:
    return v


def options_map(v: Any) -> dict[str, Any]:
    if v is None:
        return {}
    if not isinstance(v, dict) or len(v) > 16:
        raise TypeError("map")
    return v


def int_pair(v: Any) -> tuple[int, int]:
    if not isinstance(v, list) or len(v) != 2:
        raise TypeError("array of 2 integers")
    return integer(v[0]), integer(v[1])


def vector(n: int) -> Callable[[Any], list[float]]:
    def check(v: Any) -> list[float]:
        if not isinstance(v, list) or len(v) != n:
            raise TypeError(f"array of {n} numbers")
        return [number(x) for x in v]

    return check


@dataclass(frozen=True)
class Param:
    """One parameter of a served function: its name in CoppeliaSim's manual, its check,
    and its default (none: the argument is required)."""

    name: str
    check: Callable[[Any], Any]
    default: Any = _REQUIRED


#: A served function: called with the client's state and the checked arguments.
Handler = Callable[..., Any]


def check_args(func: str, params: tuple[Param, ...], args: list[Any]) -> list[Any]:
    """``args`` checked against ``params``: missing ones take their defaults, trailing
    ``None`` s (the client's ``argsL`` padding) are dropped; anything else raises
    :class:`~.state.ApiError` in CoppeliaSim's words. ``sim.callScriptFunction`` passes
    its arguments beyond ``params`` on unchecked: the script function checks them."""
    if func == "sim.callScriptFunction":
        extra = args[len(params) :]
        args = args[: len(params)]
    else:
        extra = []
        while len(args) > len(params) and args[-1] is None:
            args = args[:-1]  # argsL padding
        if len(args) > len(params):
            raise ApiError(
                f"too many arguments to '{func}': {len(args)} given, at most {len(params)} "
                f"({', '.join(p.name for p in params)})"
            )
    values = []
    for i, p in enumerate(params):
        v = args[i] if i < len(args) else None
        if v is None:
            if p.default is _REQUIRED:
                raise ApiError(
                    f"bad argument #{i + 1} to '{func}' ({p.name}: missing; "
                    f"{func}({', '.join(q.name for q in params)}))"
                )
            values.append(p.default)
            continue
        try:
            values.append(p.check(v))
        except TypeError as exc:
            raise ApiError(
                f"bad argument #{i + 1} to '{func}' ({p.name}: {exc} expected, got {type_name(v)})"
            ) from None
    return values + list(extra)


def type_name(value: Any) -> str:
    """What a client sent, in CoppeliaSim's words. The codec (and cbor2 with it) is
    imported only when an error is worded, so the table can be listed without cbor2."""
    from ..codec import _type_name as name

    return name(value)
