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

What a backend can do is asked of it here, never guessed from its name: its
:class:`BackendAbilities` (simulated or a real robot, whether it simulates the control
link's timing, whether ``puckboard calibrate`` can measure its robot, whether it reaches
its robots at an address). The built-in backends declare them in :data:`BACKENDS`, so
asking imports nothing; an installed package declares its factory's with
:func:`with_abilities` (one read when first asked), so a third-party backend gets link
timing and calibration exactly as the shipped ones do.
"""

from __future__ import annotations

import logging
import os
import pkgutil
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TypeVar

from .._extras import missing_package_message
from .._plugins import offered

__all__ = [
    "BACKENDS",
    "BACKEND_ENV",
    "ENTRY_POINT_GROUP",
    "BackendAbilities",
    "BackendEntry",
    "abilities_of",
    "backend_names",
    "default_backend",
    "open_backend",
    "register_backend",
    "with_abilities",
]

log = logging.getLogger(__name__)

#: The entry-point group an installed package names its backends in.
ENTRY_POINT_GROUP = "puckboard.backends"



@dataclass(frozen=True)
class BackendAbilities:
    """What a backend can do, for the parts of puckboard that must know (each ``False``
    unless declared, the safe answer for a backend that says nothing)."""

    #: Its robots are simulated (in this process or another simulator), not physical.
    simulated: bool = False
    #: It simulates the control link's timing itself, so a run takes the period and
    #: latency a robot's profile measured (``[link]``, ``puckboard calibrate link``).
    #: Elsewhere the link is real, or another simulator's own.
    link_timing: bool = False
    #: ``puckboard calibrate`` can measure its robot (IR response and link timing): it
    #: drives one physical e-puck, or an emulated one that answers as the robot does.
    calibratable: bool = False
    #: It reaches its robots outside this process, at an address the user gives (a host
    #: and port, or a serial device): a real robot, its emulator, another simulator.
    remote: bool = False


@dataclass(frozen=True)
class BackendEntry:
    """One backend of the registry: where its factory is, the extra that provides its
    dependencies, and what it can do (``None``: ask the factory, see
    :func:`with_abilities`)."""

    target: str
    extra: str | None = None
    abilities: BackendAbilities | None = None


BACKENDS: dict[str, BackendEntry] = {
    "embedded": BackendEntry(
        "puckboard.backends.embedded:open_embedded",
        abilities=BackendAbilities(simulated=True, link_timing=True),
    ),
    "coppeliasim": BackendEntry(
        "puckboard.backends.coppeliasim:open_coppeliasim",
        "coppeliasim",
        BackendAbilities(simulated=True, remote=True),
    ),
    "epuck2-wifi": BackendEntry(
        "puckboard.backends.epuck:open_wifi",
        abilities=BackendAbilities(calibratable=True, remote=True),
    ),
    "sercom": BackendEntry(
        "puckboard.backends.epuck:open_sercom",
        "real",
        BackendAbilities(calibratable=True, remote=True),
    ),
    "fake": BackendEntry(
        "puckboard.backends.fake:open_fake", abilities=BackendAbilities(simulated=True)
    ),
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
    for name, target, package in offered(ENTRY_POINT_GROUP, "backend", BACKENDS):
        if ":" not in target:
            log.warning(
                "%s offers backend %r as %r, not 'module:factory'; left out",
                package,
                name,
                target,
            )
            continue
        BACKENDS[name] = BackendEntry(target)


def backend_names(able: Callable[[BackendAbilities], bool] | None = None) -> list[str]:
    """Every backend name: the built-in ones, the registered and the installed ones;
    with ``able``, only those whose abilities it accepts (an installed backend that
    cannot be imported here is left out)."""
    _read_installed()
    if able is None:
        return sorted(BACKENDS)
    names = []
    for name in sorted(BACKENDS):
        try:
            if able(abilities_of(name)):
                names.append(name)
        except ImportError:
            continue
    return names


def register_backend(
    name: str, target: str, extra: str | None = None, abilities: BackendAbilities | None = None
) -> None:
    """Make ``--backend name`` resolve to ``target`` (``"module:factory"``), able to do
    what ``abilities`` says (``None``: what the factory declares, :func:`with_abilities`)."""
    if ":" not in target:
        raise ValueError(f"backend target must look like 'module:factory', got {target!r}")
    BACKENDS[name] = BackendEntry(target, extra, abilities)


def _entry(name: str) -> BackendEntry:
    if name not in BACKENDS:
        _read_installed()
    try:
        return BACKENDS[name]
    except KeyError:
        known = ", ".join(backend_names())
        raise ValueError(f"unknown backend {name!r}; known backends: {known}") from None


def resolve_backend(name: str) -> Callable[..., Any]:
    """The factory behind ``name``; a clear error for unknown names or missing extras."""
    entry = _entry(name)
    try:
        return pkgutil.resolve_name(entry.target)  # type: ignore[no-any-return]
    except ImportError as exc:
        raise ImportError(missing_package_message(f"backend {name!r}", exc, entry.extra)) from exc


#: The attribute :func:`with_abilities` sets on a factory.
_ABILITIES_ATTRIBUTE = "puckboard_abilities"

Factory = TypeVar("Factory", bound=Callable[..., Any])


def with_abilities(**abilities: bool) -> Callable[[Factory], Factory]:
    """Declare what the backend a factory opens can do (the fields of
    :class:`BackendAbilities`), for a factory an installed package offers::

        @with_abilities(calibratable=True, remote=True)
        def open_my_robot(scene=None, *, seed=0, host=None, port=None): ...

    A misspelt ability is a ``TypeError`` where the factory is defined."""
    declared = BackendAbilities(**abilities)

    def declare(factory: Factory) -> Factory:
        setattr(factory, _ABILITIES_ATTRIBUTE, declared)
        return factory

    return declare


def abilities_of(name: str) -> BackendAbilities:
    """What backend ``name`` can do: as :data:`BACKENDS` declares it, else as its factory
    does (:func:`with_abilities`; importing it), else nothing (every ability ``False``).
    An unknown name is the same ``ValueError`` as opening it."""
    entry = _entry(name)
    if entry.abilities is not None:
        return entry.abilities
    declared = getattr(resolve_backend(name), _ABILITIES_ATTRIBUTE, None)
    if declared is None:
        return BackendAbilities()
    if not isinstance(declared, BackendAbilities):
        raise TypeError(
            f"backend {name!r} declares its abilities as {declared!r}; declare them with "
            "puckboard.backends.registry.with_abilities"
        )
    return declared


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
