"""Declared value schemas: refuse malformed values at the door, naming the key.

A wrong value caught when it is written costs one clear error; caught when a layer
reads it, three ticks later, it costs an afternoon. Schemas are small callables so that
the blackboard stays independent of what it stores.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["ArraySchema", "InstanceOf", "NumberSchema", "Schema", "check"]

Schema = Callable[[Any], None]
"""A schema is any callable that raises ``ValueError`` (or ``TypeError``) for a bad value."""


@dataclass(frozen=True)
class InstanceOf:
    """The value must be an instance of ``cls`` (whose constructor validates its fields)."""

    cls: type

    def __call__(self, value: Any) -> None:
        if not isinstance(value, self.cls):
            shape = getattr(value, "shape", None)
            got = type(value).__name__ + (f" of shape {shape}" if shape is not None else "")
            raise ValueError(f"expected a {self.cls.__name__} record, got {got}")

    def __str__(self) -> str:
        return f"a {self.cls.__name__} record"


@dataclass(frozen=True)
class NumberSchema:
    """A finite real number, optionally within [low, high]."""

    low: float = -math.inf
    high: float = math.inf

    def __call__(self, value: Any) -> None:
        if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
            raise ValueError(f"expected a number, got {type(value).__name__}")
        if not math.isfinite(value):
            raise ValueError(f"expected a finite number, got {value!r}")
        if not self.low <= value <= self.high:
            raise ValueError(f"expected a number in [{self.low}, {self.high}], got {value!r}")


@dataclass(frozen=True)
class ArraySchema:
    """A numeric array of a given shape (``None`` in the shape means any length)."""

    shape: tuple[int | None, ...]
    low: float = -math.inf
    high: float = math.inf

    def __call__(self, value: Any) -> None:
        try:
            arr = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"expected a numeric array, got {type(value).__name__}") from None
        if arr.ndim != len(self.shape) or any(
            want is not None and want != got for want, got in zip(self.shape, arr.shape)
        ):
            raise ValueError(f"expected an array of shape {self.shape}, got shape {arr.shape}")
        if not np.all(np.isfinite(arr)):
            raise ValueError("expected finite numbers, got NaN or infinity")
        if np.any(arr < self.low) or np.any(arr > self.high):
            raise ValueError(f"expected values in [{self.low}, {self.high}]")


def check(key: str, schema: Schema | None, value: Any) -> None:
    """Run ``schema`` on ``value``; re-raise its complaint as a ValueError naming ``key``."""
    if schema is None:
        return
    try:
        schema(value)
    except (ValueError, TypeError) as exc:
        raise ValueError(f"blackboard key {key!r}: {exc}") from exc
