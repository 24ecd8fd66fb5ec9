"""Backends by name, imported only when used (like gpiozero's pin factories).

``puckboard run --backend NAME`` and :func:`open_backend` look names up here. Each entry
is ``"module:callable"``; the module is imported lazily, so a backend whose extra is not
installed costs nothing until someone asks for it, and then fails with a message that
says which extra to install.
"""

from __future__ import annotations

import pkgutil
from collections.abc import Callable
from typing import Any

__all__ = ["BACKENDS", "open_backend", "register_backend"]

BACKENDS: dict[str, tuple[str, str | None]] = {
    # name: ("module:factory", extra that provides its dependencies)
    "embedded": ("puckboard.adapters.embedded:open_embedded", None),
    "coppeliasim": ("puckboard.adapters.vrep:open_coppeliasim", "coppeliasim"),
    "epuck2-wifi": ("puckboard.adapters.real:open_wifi", None),
    "sercom": ("puckboard.adapters.real:open_sercom", "real"),
}


def register_backend(name: str, target: str, extra: str | None = None) -> None:
    """Make ``--backend name`` resolve to ``target`` (``"module:factory"``)."""
    if ":" not in target:
        raise ValueError(f"backend target must look like 'module:factory', got {target!r}")
    BACKENDS[name] = (target, extra)


def resolve_backend(name: str) -> Callable[..., Any]:
    """The factory behind ``name``; a clear error for unknown names or missing extras."""
    try:
        target, extra = BACKENDS[name]
    except KeyError:
        known = ", ".join(sorted(BACKENDS))
        raise ValueError(f"unknown backend {name!r}; known backends: {known}") from None
    try:
        return pkgutil.resolve_name(target)  # type: ignore[no-any-return]
    except ImportError as exc:
        hint = f" (install it with: pip install 'puckboard[{extra}]')" if extra else ""
        raise ImportError(f"backend {name!r} needs a missing package: {exc.name}{hint}") from exc


def open_backend(name: str, *args: Any, **options: Any) -> Any:
    """Open backend ``name`` with the factory's own arguments."""
    return resolve_backend(name)(*args, **options)
