"""Backends by name, imported only when used (like gpiozero's pin factories).

``puckboard run --backend NAME`` and :func:`open_backend` look names up here. Each entry
is ``"module:callable"``; the module is imported lazily, so a backend whose extra is not
installed costs nothing until someone asks for it, and then fails with a message that
says which extra to install.

A package adds a backend without editing puckboard the way a gpiozero pin factory is
found: an entry point in the ``puckboard.backends`` group, named for the backend and
pointing at its factory (in its ``pyproject.toml``::

    [project.entry-points."puckboard.backends"]
    my-robot = "my_package.robot:open_my_robot"

). Installed packages are read once, the first time a name is not among the built-in
ones (or the list of names is wanted), so an ordinary run never scans them. A built-in
name is never replaced by an installed one (a warning names the package that tried);
:func:`register_backend` replaces any.
"""

from __future__ import annotations

import logging
import os
import pkgutil
from collections.abc import Callable
from typing import Any

from .._extras import missing_package_message

__all__ = [
    "BACKENDS",
    "BACKEND_ENV",
    "ENTRY_POINT_GROUP",
    "backend_names",
    "default_backend",
    "open_backend",
    "register_backend",
]

log = logging.getLogger(__name__)

#: The entry-point group an installed package names its backends in.
ENTRY_POINT_GROUP = "puckboard.backends"

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
#: Whether the installed packages' backends have been read into :data:`BACKENDS`.
_installed_read = False


def _read_installed() -> None:
    """Add the installed packages' backends (entry points) to :data:`BACKENDS`, once."""
    global _installed_read
    if _installed_read:
        return
    _installed_read = True
    from importlib.metadata import entry_points

    for ep in entry_points(group=ENTRY_POINT_GROUP):
        package = ep.dist.name if ep.dist is not None else "an installed package"
        if ep.name in BACKENDS:
            log.warning(
                "%s offers a backend %r, which puckboard already has; keeping puckboard's",
                package,
                ep.name,
            )
            continue
        if ":" not in ep.value:
            log.warning(
                "%s offers backend %r as %r, not 'module:factory'; left out",
                package,
                ep.name,
                ep.value,
            )
            continue
        BACKENDS[ep.name] = (ep.value, None)


def backend_names() -> list[str]:
    """Every backend name: the built-in ones, the registered and the installed ones."""
    _read_installed()
    return sorted(BACKENDS)


def register_backend(name: str, target: str, extra: str | None = None) -> None:
    """Make ``--backend name`` resolve to ``target`` (``"module:factory"``)."""
    if ":" not in target:
        raise ValueError(f"backend target must look like 'module:factory', got {target!r}")
    BACKENDS[name] = (target, extra)


def resolve_backend(name: str) -> Callable[..., Any]:
    """The factory behind ``name``; a clear error for unknown names or missing extras."""
    if name not in BACKENDS:
        _read_installed()
    try:
        target, extra = BACKENDS[name]
    except KeyError:
        known = ", ".join(backend_names())
        raise ValueError(f"unknown backend {name!r}; known backends: {known}") from None
    try:
        return pkgutil.resolve_name(target)  # type: ignore[no-any-return]
    except ImportError as exc:
        raise ImportError(missing_package_message(f"backend {name!r}", exc, extra)) from exc


def default_backend() -> str:
    """The backend named by ``$PUCKBOARD_BACKEND``, else ``"embedded"``; checked by name."""
    name = os.environ.get(BACKEND_ENV, "").strip() or DEFAULT_BACKEND
    if name not in BACKENDS:
        _read_installed()
    if name not in BACKENDS:
        known = ", ".join(backend_names())
        raise ValueError(f"{BACKEND_ENV}={name!r} names no backend; use one of {known} or unset it")
    return name


def open_backend(name: str | None, *args: Any, **options: Any) -> Any:
    """Open backend ``name`` (``None``: :func:`default_backend`) with its factory's arguments."""
    return resolve_backend(name if name is not None else default_backend())(*args, **options)
