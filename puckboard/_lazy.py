"""A package's names loaded on first use (PEP 562), as ``puckboard`` loads its own.

A package whose ``__init__`` imported its parts would load them (and numpy) for anyone
who imports one small module of it: the command line reads names from
:mod:`puckboard.scenario` and :mod:`puckboard.sweep` while it builds its parser, before
numpy may be imported (:mod:`puckboard.sweep.signals`).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping, Sequence
from typing import Any

__all__ = ["lazy_names"]


def lazy_names(
    package: str, homes: Mapping[str, str], names: Sequence[str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """A package's ``__getattr__`` and ``__dir__``: each name of ``homes`` imported from
    its module (relative to ``package``, or absolute) the first time it is asked for,
    then kept in the package; ``names`` is what ``dir()`` lists (its ``__all__``)."""
    import sys

    def __getattr__(name: str) -> Any:
        module = homes.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module, package), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__() -> list[str]:
        return sorted(names)

    return __getattr__, __dir__
