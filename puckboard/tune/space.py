"""The search space: which settings of a controller a study moves, and across what.

A parameter is written ``PATH=LOW:HIGH`` with an optional kind after the range, or
``PATH=A,B[,...]`` for a choice:

* ``layer.LineFollow.inner_factor=0.1:0.9`` — a real number, drawn uniformly;
* ``layer.FrontObstacleLeftTurn.hold_steps=1:9:int`` — a whole number, both ends included;
* ``speed=0.01:0.1:log`` — a real number drawn uniformly in its logarithm (for gains that
  span decades); ``:int:log`` combines both;
* ``layer.LineFollow.recovery=true,false`` (or ``PATH=word1,word2``) —
  one of the values listed (Optuna's categorical distribution), for a setting that is
  true or false, or a word: a range would make a bool a number.

``PATH`` is a keyword of the controller's factory (``speed``: episodes receive it as
``controller.speed``) or any ``layer.<Name>.<attribute>`` that ``sweep --set`` accepts.
Every name is checked against the controller itself (its factory's signature and its
layers' :meth:`~puckboard.behaviours.Layer.parameters`, built once,
:func:`shipped_values`), and so is its kind against the value the controller ships: a
whole-number range for a real attribute would turn the shipped 0.5 into 0 or 1, and a
range for a bool or a word has no meaning. Each mistake is refused before a single
episode runs, with the names that exist.
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, TypeAlias

if TYPE_CHECKING:
    from optuna.trial import Trial

__all__ = [
    "KINDS",
    "Choice",
    "Param",
    "SpaceError",
    "Tunable",
    "check_space",
    "parse_param",
    "shipped_values",
    "trial_zero",
]

#: The kinds a range may name after ``LOW:HIGH``.
KINDS = ("int", "log")

_CONTROLLER = "controller."
_EXAMPLE = (
    "e.g. layer.LineFollow.inner_factor=0.1:0.9, speed=0.02:0.1:log, X=1:9:int or "
    "layer.LineFollow.recovery=true,false"
)

#: A value a choice may take: what Optuna's categorical distribution stores as itself.
ChoiceValue: TypeAlias = "bool | int | float | str"


class SpaceError(ValueError):
    """A search space the study cannot use; the message names the parameter and the fix."""


def _label(name: str) -> str:
    return name[len(_CONTROLLER) :] if name.startswith(_CONTROLLER) else name


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
        return _label(self.name)

    @property
    def ends(self) -> tuple[float, ...]:
        """The values an episode must accept before any runs: both ends."""
        return (self.low, self.high)

    def holds(self, value: Any) -> bool:
        """Whether ``value`` is one this parameter can draw, as it is (no rounding)."""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            return False
        if self.integer and not float(value).is_integer():
            return False
        return self.low <= value <= self.high

    def suggest(self, trial: Trial) -> float | int:
        """Draw this parameter's value for an Optuna ``trial``."""
        if self.integer:
            return int(trial.suggest_int(self.name, int(self.low), int(self.high), log=self.log))
        return float(trial.suggest_float(self.name, self.low, self.high, log=self.log))


@dataclass(frozen=True)
class Choice:
    """One tuned setting drawn from the values listed (true/false, words or numbers)."""

    name: str
    choices: tuple[ChoiceValue, ...]

    @property
    def spec(self) -> str:
        return f"{self.label}={','.join(_text(c) for c in self.choices)}"

    @property
    def label(self) -> str:
        return _label(self.name)

    @property
    def ends(self) -> tuple[ChoiceValue, ...]:
        return self.choices

    def holds(self, value: Any) -> bool:
        return any(type(value) is type(c) and value == c for c in self.choices)

    def suggest(self, trial: Trial) -> ChoiceValue:
        return trial.suggest_categorical(self.name, self.choices)  # type: ignore[return-value]  # one of choices: no None


def _number(value: float) -> str:
    return str(int(value)) if float(value).is_integer() else repr(float(value))


def _text(value: ChoiceValue) -> str:
    """A choice as ``--set`` reads it back (``true``, a bare word, a number)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return value if isinstance(value, str) else _number(value)


def parse_param(text: str) -> Param | Choice:
    """Parse ``PATH=LOW:HIGH[:int][:log]`` or ``PATH=A,B[,...]``; :class:`SpaceError`
    names what was wrong."""
    path, sep, rest = text.partition("=")
    path = path.strip()
    if not sep or not path:
        raise SpaceError(f"--param {text!r}: expected PATH=LOW:HIGH or PATH=A,B ({_EXAMPLE})")
    name = path if path.startswith(("layer.", _CONTROLLER)) else _CONTROLLER + path
    if "," in rest:
        return Choice(name, _choices(text, rest))
    parts = [p.strip() for p in rest.split(":")]
    if len(parts) < 2:
        raise SpaceError(f"--param {text!r}: expected PATH=LOW:HIGH or PATH=A,B ({_EXAMPLE})")
    kinds = parts[2:]
    unknown = [k for k in kinds if k not in KINDS]
    if unknown or len(set(kinds)) != len(kinds):
        raise SpaceError(
            f"--param {text!r}: after LOW:HIGH give int, log or int:log, not {':'.join(kinds)}"
        )
    try:
        low, high = float(parts[0]), float(parts[1])
    except ValueError:
        raise SpaceError(f"--param {text!r}: LOW and HIGH must be numbers ({_EXAMPLE})") from None
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
    return Param(name, low, high, integer=integer, log=log)


def _choices(text: str, rest: str) -> tuple[ChoiceValue, ...]:
    from ..scenario.overrides import parse_value

    parts = [p.strip() for p in rest.split(",")]
    if any(not p for p in parts):
        raise SpaceError(f"--param {text!r}: an empty choice; list the values, e.g. true,false")
    values = [parse_value(p) for p in parts]
    if any(isinstance(v, float) and not math.isfinite(v) for v in values):
        raise SpaceError(f"--param {text!r}: choices must be finite numbers, true/false or words")
    keys = [(type(v).__name__, v) for v in values]
    if len(set(keys)) != len(keys):
        raise SpaceError(f"--param {text!r}: a choice is listed twice; list each once")
    return tuple(values)


@dataclass(frozen=True)
class Tunable:
    """What a controller offers to tune, read from one build of it: its factory's
    keywords (and whether it takes any, ``**params``), and the value it ships for every
    name (``layer.<Name>.<attribute>`` as built, ``controller.<keyword>`` defaults)."""

    controller: str
    keywords: tuple[str, ...]
    open_ended: bool
    values: Mapping[str, Any]

    @property
    def numbers(self) -> list[str]:
        """The layers' attributes that are numbers (what a range fits)."""
        return [
            name
            for name, value in self.values.items()
            if name.startswith("layer.") and _is_number(value)
        ]

    def has(self, name: str) -> bool:
        return name in self.values or (
            name.startswith(_CONTROLLER)
            and (self.open_ended or name[len(_CONTROLLER) :] in self.keywords)
        )


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def shipped_values(controller: str) -> Tunable:
    """Build ``controller`` once and read what it offers to tune (:class:`Tunable`)."""
    from ..behaviours import load_controller
    from ..behaviours.presets import resolve_factory

    factory = resolve_factory(controller)
    keywords: list[str] = []
    open_ended = False
    values: dict[str, Any] = {}
    for layer in load_controller(controller).every_layer:
        for attr, value in sorted(layer.parameters().items()):
            values.setdefault(f"layer.{layer.name}.{attr}", value)
    for p in inspect.signature(factory).parameters.values():
        if p.kind is inspect.Parameter.VAR_KEYWORD:
            open_ended = True
        elif p.kind in (inspect.Parameter.POSITIONAL_OR_KEYWORD, inspect.Parameter.KEYWORD_ONLY):
            keywords.append(p.name)
            if p.default is not inspect.Parameter.empty:
                values[_CONTROLLER + p.name] = p.default
    return Tunable(controller, tuple(keywords), open_ended, values)


def check_space(params: Sequence[Param | Choice], controller: str | Tunable) -> Tunable:
    """Refuse a parameter ``controller`` does not have, one given twice, or one whose
    kind is not its shipped value's (a real range for a whole number, a whole-number range
    for a real one, a range for true/false or a word, a choice of another type); the
    message lists the names that exist. Returns what the controller offers."""
    seen: set[str] = set()
    for param in params:
        if param.name in seen:
            raise SpaceError(f"--param {param.label} is given twice; give each parameter once")
        seen.add(param.name)
    tunable = controller if isinstance(controller, Tunable) else shipped_values(controller)
    for param in params:
        if not tunable.has(param.name):
            raise SpaceError(
                f"--param {param.label}: controller {tunable.controller!r} has no such "
                f"parameter; its factory's keywords: {', '.join(tunable.keywords) or 'none'}; "
                f"its layers' attributes: {', '.join(tunable.numbers) or 'none'}"
            )
        if param.name in tunable.values:
            _check_kind(param, tunable.values[param.name])
    return tunable


def _check_kind(param: Param | Choice, value: Any) -> None:
    """``param``'s kind against the controller's own ``value`` of it."""
    name = param.label
    if isinstance(value, bool):
        kind, fix = "true or false", f"--param {name}=true,false"
    elif isinstance(value, str):
        kind, fix = f"a word ({value!r})", f"list the words to try, e.g. --param {name}={value},..."
    elif not _is_number(value):
        raise SpaceError(
            f"--param {param.spec}: {name} is a {type(value).__name__} ({value!r}), not a number "
            "or one value: tune searches numbers, true/false and words; set it in the "
            "controller's factory instead"
        )
    else:
        kind, fix = "", ""
    if isinstance(param, Param):
        if kind:
            raise SpaceError(f"--param {param.spec}: {name} is {kind}, not a number; search it "
                             f"as a choice: {fix}")  # fmt: skip
        if isinstance(value, int) and not param.integer:
            raise SpaceError(
                f"--param {param.spec}: {name} is a whole number; add :int to its range"
            )
        if isinstance(value, float) and param.integer:
            raise SpaceError(
                f"--param {param.spec}: {name} is a real number (ships {value!r}); an int range "
                "would round it: drop :int"
            )
        return
    wanted = (
        bool if isinstance(value, bool)
        else str if isinstance(value, str)
        else int if isinstance(value, int)
        else float
    )  # fmt: skip
    if not all(_fits(wanted, c) for c in param.choices):
        what = kind or ("a whole number" if wanted is int else "a number")
        raise SpaceError(
            f"--param {param.spec}: {name} is {what}; every choice must be one"
            + (f" ({fix})" if fix else "")
        )


def _fits(wanted: type, choice: ChoiceValue) -> bool:
    if wanted is float:
        return _is_number(choice)
    return type(choice) is wanted


def trial_zero(params: Sequence[Param | Choice], tunable: Tunable) -> dict[str, Any]:
    """The controller as shipped, as a trial: its own value of every parameter, when each
    lies in the space as it is (nothing rounded or converted); else empty."""
    values: dict[str, Any] = {}
    for param in params:
        value: Any = tunable.values.get(param.name)
        if param.holds(value):
            real = isinstance(param, Param) and not param.integer
            values[param.name] = float(value) if real else value
    return values if len(values) == len(params) else {}
