"""The search space: which numbers of a controller a study moves, and across what range.

A parameter is written ``PATH=LOW:HIGH`` with an optional kind after the range:

* ``layer.LineFollow.inner_factor=0.1:0.9`` — a real number, drawn uniformly;
* ``layer.FrontObstacleLeftTurn.hold_steps=1:9:int`` — a whole number, both ends included;
* ``speed=0.01:0.1:log`` — a real number drawn uniformly in its logarithm (for gains that
  span decades); ``:int:log`` combines both.

``PATH`` is a keyword of the controller's factory (``speed``: episodes receive it as
``controller.speed``) or any ``layer.<Name>.<attribute>`` that ``sweep --set`` accepts.
Every name is checked against the controller itself (its factory's signature and its
layers' :meth:`~puckboard.behaviours.Layer.parameters`), so a typo is refused before a
single episode runs, with the names that exist.
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

__all__ = [
    "KINDS",
    "Param",
    "SpaceError",
    "check_space",
    "own_values",
    "parse_param",
    "tunable_names",
]

#: The kinds a range may name after ``LOW:HIGH``.
KINDS = ("int", "log")

_CONTROLLER = "controller."


class SpaceError(ValueError):
    """A search space the study cannot use; the message names the parameter and the fix."""


@dataclass(frozen=True)
class Param:
    """One tuned number: its episode parameter name (``layer.X.y`` or ``controller.kw``),
    its range (both ends included) and how it is drawn."""

    name: str
    low: float
    high: float
    integer: bool = False
    log: bool = False

    @property
    def spec(self) -> str:
        """The parameter as the command line writes it (what made it)."""
        kinds = "".join(f":{k}" for k, on in (("int", self.integer), ("log", self.log)) if on)
        return f"{self.label}={_number(self.low)}:{_number(self.high)}{kinds}"

    @property
    def label(self) -> str:
        """``speed`` for a factory keyword, the full name for a layer's attribute."""
        return self.name[len(_CONTROLLER) :] if self.name.startswith(_CONTROLLER) else self.name

    def suggest(self, trial: Any) -> float | int:
        """Draw this parameter's value for an Optuna ``trial``."""
        if self.integer:
            return int(trial.suggest_int(self.name, int(self.low), int(self.high), log=self.log))
        return float(trial.suggest_float(self.name, self.low, self.high, log=self.log))


def _number(value: float) -> str:
    return str(int(value)) if float(value).is_integer() else repr(float(value))


def parse_param(text: str) -> Param:
    """Parse ``PATH=LOW:HIGH[:int][:log]``; :class:`SpaceError` names what was wrong."""
    path, sep, rest = text.partition("=")
    path = path.strip()
    example = "e.g. layer.LineFollow.inner_factor=0.1:0.9, speed=0.02:0.1:log or X=1:9:int"
    if not sep or not path:
        raise SpaceError(f"--param {text!r}: expected PATH=LOW:HIGH ({example})")
    parts = [p.strip() for p in rest.split(":")]
    if len(parts) < 2:
        raise SpaceError(f"--param {text!r}: expected PATH=LOW:HIGH ({example})")
    kinds = parts[2:]
    unknown = [k for k in kinds if k not in KINDS]
    if unknown or len(set(kinds)) != len(kinds):
        raise SpaceError(
            f"--param {text!r}: after LOW:HIGH give int, log or int:log, not {':'.join(kinds)}"
        )
    try:
        low, high = float(parts[0]), float(parts[1])
    except ValueError:
        raise SpaceError(f"--param {text!r}: LOW and HIGH must be numbers ({example})") from None
    if not (math.isfinite(low) and math.isfinite(high)):
        raise SpaceError(f"--param {text!r}: LOW and HIGH must be finite numbers")
    integer, log = "int" in kinds, "log" in kinds
    if integer and not (low.is_integer() and high.is_integer()):
        raise SpaceError(f"--param {text!r}: an int range needs whole numbers at both ends")
    if low > high:
        raise SpaceError(
            f"--param {text!r}: the range is reversed; write the smaller end first "
            f"({path}={parts[1]}:{parts[0]})"
        )
    if low == high:
        raise SpaceError(
            f"--param {text!r}: the range is empty; give two different ends, or fix the value "
            f"with --set instead"
        )
    if log and low <= 0:
        raise SpaceError(f"--param {text!r}: a log range needs LOW > 0")
    name = path if path.startswith(("layer.", _CONTROLLER)) else _CONTROLLER + path
    return Param(name, low, high, integer=integer, log=log)


def tunable_names(controller: str) -> tuple[list[str], list[str], bool]:
    """What ``controller`` offers to tune: its factory's keywords, its layers' numeric
    parameters (``layer.<Name>.<attribute>``), and whether the factory takes any keyword
    (``**params``)."""
    from ..behaviours import load_controller
    from ..behaviours.presets import resolve_factory

    factory = resolve_factory(controller)
    keywords: list[str] = []
    open_ended = False
    for p in inspect.signature(factory).parameters.values():
        if p.kind is inspect.Parameter.VAR_KEYWORD:
            open_ended = True
        elif p.kind in (inspect.Parameter.POSITIONAL_OR_KEYWORD, inspect.Parameter.KEYWORD_ONLY):
            keywords.append(p.name)
    built = load_controller(controller)
    layered = [
        f"layer.{layer.name}.{attr}"
        for layer in built.every_layer
        for attr, value in sorted(layer.parameters().items())
        if isinstance(value, (int, float)) and not isinstance(value, bool)
    ]
    return keywords, list(dict.fromkeys(layered)), open_ended


def check_space(params: Sequence[Param], controller: str) -> None:
    """Refuse a parameter ``controller`` does not have, one given twice, or a whole-number
    attribute given a real range; the message lists the names that exist."""
    seen: set[str] = set()
    for param in params:
        if param.name in seen:
            raise SpaceError(f"--param {param.label} is given twice; give each parameter once")
        seen.add(param.name)
    keywords, layered, open_ended = tunable_names(controller)
    known = {_CONTROLLER + k for k in keywords} | set(layered)
    for param in params:
        if param.name in known or (open_ended and param.name.startswith(_CONTROLLER)):
            continue
        raise SpaceError(
            f"--param {param.label}: controller {controller!r} has no such parameter; its "
            f"factory's keywords: {', '.join(keywords) or 'none'}; its layers' attributes: "
            f"{', '.join(layered) or 'none'}"
        )
    _check_whole_numbers(params, controller)


def own_values(controller: str) -> dict[str, Any]:
    """``controller``'s own value of every name there is to tune: its layers' attributes
    as built, its factory's keywords' defaults (``controller.<keyword>``)."""
    from ..behaviours import load_controller
    from ..behaviours.presets import resolve_factory

    values: dict[str, Any] = {
        f"layer.{layer.name}.{attr}": value
        for layer in load_controller(controller).every_layer
        for attr, value in layer.parameters().items()
    }
    for p in inspect.signature(resolve_factory(controller)).parameters.values():
        if p.default is not inspect.Parameter.empty:
            values[_CONTROLLER + p.name] = p.default
    return values


def _check_whole_numbers(params: Sequence[Param], controller: str) -> None:
    current: Mapping[str, Any] = own_values(controller)
    for param in params:
        value = current.get(param.name)
        if isinstance(value, int) and not isinstance(value, bool) and not param.integer:
            raise SpaceError(
                f"--param {param.spec}: {param.name} is a whole number; add :int to its range"
            )
