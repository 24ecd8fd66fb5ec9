"""Backends by name, imported only when used (like gpiozero's pin factories).

``puckboard run --backend NAME`` and :func:`open_backend` look names up here. Each entry
is ``"module:callable"``; the module is imported lazily, so a backend whose extra is not
installed costs nothing until someone asks for it, and then fails with a message that
says which extra to install.
"""

from __future__ import annotations

import os
import pkgutil
from collections.abc import Callable
from typing import Any

from .._extras import missing_package_message

__all__ = ["BACKENDS", "BACKEND_ENV", "default_backend", "open_backend", "register_backend"]

BACKENDS: dict[str, tuple[str, str | None]] = {
    # name: ("module:factory", extra that provides its dependencies)
    "embedded": ("puckboard.backends.embedded:open_embedded", None),
    "coppeliasim": ("puckboard.backends.coppeliasim:open_coppeliasim", "coppeliasim"),
    "epuck2-wifi": ("puckboard.backends.epuck:open_wifi", None),
    "sercom": ("puckboard.backends.epuck:open_sercom", "real"),
    "fake": ("puckboard.backends.fake:open_fake", None),
}

#: Environment variable naming the backend used when none is given (as gpiozero's
#: ``GPIOZERO_PIN_FACTORY`` picks its pin factory): ``PUCKBOARD_BACKEND=fake pytest``
#: runs a student's tests against the fake robot without changing a line.
BACKEND_ENV = "PUCKBOARD_BACKEND"
#: The backend used when neither the caller nor the environment names one.
DEFAULT_BACKEND = "embedded"


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
        raise ImportError(missing_package_message(f"backend {name!r}", exc, extra)) from exc


def default_backend() -> str:
    """The backend named by ``$PUCKBOARD_BACKEND``, else ``"embedded"``; checked by name."""
    name = os.environ.get(BACKEND_ENV, "").strip() or DEFAULT_BACKEND
    if name not in BACKENDS:
        known = ", ".join(sorted(BACKENDS))
        raise ValueError(f"{BACKEND_ENV}={name!r} names no backend; use one of {known} or unset it")
    return name


def open_backend(name: str | None, *args: Any, **options: Any) -> Any:
    """Open backend ``name`` (``None``: :func:`default_backend`) with its factory's arguments."""
    return resolve_backend(name if name is not None else default_backend())(*args, **options)
