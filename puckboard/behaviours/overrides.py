"""Layer overrides: ``layer.<LayerName>.<attribute>`` set on the layers of controllers.

The controllers' part of the override dialect (:mod:`puckboard.scenario.overrides` holds
the scene's, and reads ``NAME=VALUE`` text): ``--set layer.LineFollow.inner_factor=0.3``
sets that parameter on the ``LineFollow`` layer of every controller that has one. A
value takes the type of the parameter it replaces, since a command line gives text and
the text ``"no"`` is true in Python.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from .controller import Controller
from .layer import Layer

__all__ = ["CONTROLLER_PREFIX", "apply_layer_overrides", "factory_keywords", "layer_target"]

#: Prefix of the overrides handed to the controller factory as keywords.
CONTROLLER_PREFIX = "controller."


def factory_keywords(overrides: Mapping[str, Any]) -> dict[str, Any]:
    """The ``controller.<keyword>`` overrides as the factory's keyword arguments
    (``{"controller.speed": 0.1}`` → ``{"speed": 0.1}``): a preset's speed is an argument
    of its factory, not an attribute of one layer."""
    return {
        name[len(CONTROLLER_PREFIX) :]: value
        for name, value in overrides.items()
        if name.startswith(CONTROLLER_PREFIX)
    }


_TRUE = frozenset({"true", "yes", "on", "1"})
_FALSE = frozenset({"false", "no", "off", "0"})


def layer_target(name: str) -> tuple[str, str] | None:
    """``(LayerName, attribute)`` of a ``layer.<LayerName>.<attribute>`` override;
    ``None`` for a name that is no layer override; ``ValueError`` for one that starts
    ``layer.`` but is not of that form."""
    if not name.startswith("layer."):
        return None
    parts = name.split(".")
    if len(parts) != 3 or not parts[1] or not parts[2]:
        raise ValueError(f"override {name!r} must look like layer.<LayerName>.<attribute>")
    return parts[1], parts[2]


def apply_layer_overrides(
    controllers: Mapping[str, Controller], overrides: Mapping[str, Any]
) -> None:
    """Set ``layer.<LayerName>.<attribute>`` overrides on every controller that has that
    layer; an error when no controller has it or the layer has no such attribute. Other
    names are left alone."""
    for name, value in overrides.items():
        target = layer_target(name)
        if target is None:
            continue
        layer_name, attr = target
        found = False
        for ctrl in controllers.values():
            try:
                layer: Layer = ctrl.find(layer_name)
            except KeyError:
                continue
            params = layer.parameters()
            if attr not in params:
                raise ValueError(
                    f"override {name!r}: layer {layer_name} has no parameter {attr!r}; "
                    f"its parameters: {', '.join(sorted(params))}"
                )
            setattr(layer, attr, _as_type_of(params[attr], name, value))
            found = True
        if not found:
            layers = sorted({n.name for c in controllers.values() for n in c.every_layer})
            raise ValueError(
                f"override {name!r}: no controller has a layer {layer_name!r}; "
                f"layers: {', '.join(layers)}"
            )


def _as_type_of(current: Any, name: str, value: Any) -> Any:
    """``value`` as the type of the parameter's ``current`` value, or ``ValueError``.

    A command line gives text: ``recovery=no`` must switch recovery off, not store the
    string ``"no"``, which is true. Booleans take true/false, yes/no, on/off or 1/0 and
    nothing else; whole-number parameters take whole numbers, others any number.
    Parameters of other types (text, tuples) take the value as given.
    """
    if isinstance(current, bool):
        if isinstance(value, bool):
            return value
        text = str(value).strip().lower() if isinstance(value, (str, int)) else None
        if text in _TRUE or text in _FALSE:
            return text in _TRUE
        raise ValueError(
            f"override {name!r} is a boolean: use true/false, yes/no, on/off or 1/0, got {value!r}"
        )
    if isinstance(current, (int, float)):
        number: Any = value
        if isinstance(value, str):
            try:
                number = float(value)
            except ValueError:
                number = None
        if isinstance(number, bool) or not isinstance(number, (int, float)):
            kind = "a whole number" if isinstance(current, int) else "a number"
            raise ValueError(
                f"override {name!r} needs {kind} "
                f"(the parameter is {type(current).__name__}), got {value!r}"
            )
        if isinstance(current, int):
            if not float(number).is_integer():
                raise ValueError(
                    f"override {name!r} needs a whole number (the parameter is int), got {value!r}"
                )
            return int(number)
        return float(number)
    return value
