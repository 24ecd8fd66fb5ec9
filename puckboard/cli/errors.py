"""The command line's error type and how a failure becomes one line.

:class:`CliError` is bad input or a run that could not go on, printed as one line by
:func:`puckboard.cli.main`; the rest turn what went wrong (a missing optional package, a
lost robot or simulator, the user's own code raising) into that line, or into Python's
own account of the user's code above it.
"""

from __future__ import annotations

import contextlib
import logging
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .._extras import missing_package_message

if TYPE_CHECKING:
    from ..control.episode import Episode

__all__ = [
    "CliError",
    "connection_loss_in_one_line",
    "connection_lost_error",
    "controller_error",
    "first_line",
    "missing_extra",
    "user_code_error",
]


class CliError(Exception):
    """Bad input on the command line: printed as one line, exit status 2.

    ``details`` (optional) is printed above that line as it is: what Python shows for an
    error in the user's own file (file, line, caret, message), which one line cannot
    hold. ``status`` is the exit status: 2 for input refused before anything ran, 1 for
    a run that could not go on (a robot or simulator that went away).
    """

    def __init__(self, message: str, *, details: str | None = None, status: int = 2) -> None:
        super().__init__(message)
        self.details = details
        self.status = status


def first_line(exc: BaseException) -> str:
    """The first line of ``exc``'s message (its type's name if it has none): what a
    one-line error shows of an exception whose message runs on."""
    text = str(exc).strip() or type(exc).__name__
    return text.splitlines()[0]


def missing_extra(exc: ImportError, what: str) -> CliError:
    """One line for a missing optional package that names the extra to install.

    Library code that already worded its ImportError for users (it names a
    ``puckboard[...]`` extra) keeps its words; a bare ``No module named 'rich'`` becomes
    ``"<what> needs a missing package: rich (install it with: pip install
    'puckboard[cli]')"``, the wording of ``puckboard run --backend coppeliasim``.
    """
    text = (str(exc).strip().splitlines() or [""])[0]
    if "puckboard[" in text:
        return CliError(text)
    return CliError(missing_package_message(what, exc))


def controller_error(exc: BaseException, spec: str | None) -> CliError | None:
    """What every command that builds a controller from ``spec`` (``None``: each robot's
    from the scene) says when that failed; ``None`` for an error that is not about the
    controller (a bug, shown with its traceback).

    What puckboard refused in what the code built (a class where an object belongs, a
    layer without ``command``, an empty controller) is one line saying what to write: a
    traceback through the user's factory would add nothing to it. An exception of the
    user's own code is shown as Python shows it (:func:`user_code_error`); any other bad
    spec (no such file or factory) is one line.
    """
    from ..errors import PuckboardError

    if isinstance(exc, PuckboardError):
        return CliError(first_line(exc))
    shown = user_code_error(exc, f"the controller {spec!r}" if spec else "a robot's controller")
    if shown is not None:
        return shown
    if isinstance(exc, (ValueError, TypeError, ImportError)):
        return CliError(first_line(exc))
    return None


def user_code_error(exc: BaseException, what: str, *loaders: Any) -> CliError | None:
    """``exc`` as Python shows it for the user's own file (file, line, caret, message,
    and none of puckboard's frames) with one line under it, when ``exc`` was raised by
    code that ``loaders`` ran for the user; ``None`` for any other error.

    ``what`` names that code for the line ("the controller 'my.py:make'"). Without
    ``loaders`` they are the controller loader's, the usual case. A syntax error is
    input refused before anything ran (status 2); any other error of that code is the
    code failing (status 1), as ``python file.py`` would end.
    """
    from ..usercode import user_traceback

    if not loaders:
        from ..behaviours.presets import load_controller, resolve_factory

        loaders = (load_controller, resolve_factory)
    text = user_traceback(exc, *loaders)
    if text is None:
        return None
    if isinstance(exc, SyntaxError):
        where = f" in {Path(exc.filename).name}" if exc.filename else ""
        return CliError(
            f"{what} has a syntax error{where} (shown above); fix it and run again", details=text
        )
    return CliError(
        f"{what} raised {type(exc).__name__} (shown above); fix it and run again",
        details=text,
        status=1,
    )


@contextlib.contextmanager
def connection_loss_in_one_line(episode: Episode) -> Iterator[None]:
    """Run ``episode`` inside this block: a lost simulator or robot ends the command
    with :func:`connection_lost_error`'s one line instead of a traceback.

    While the wheels are stopped and the robots closed, every robot's attempts log a
    warning naming the lost connection, the same words once per robot and attempt;
    the one line says all of it, so those warnings are held back, and logged as usual
    when the run ends any other way.
    """
    from ..errors import ConnectionLostError

    held: list[logging.LogRecord] = []

    def hold(record: logging.LogRecord) -> bool:
        args = record.args if isinstance(record.args, tuple) else ()
        if record.levelno == logging.WARNING and any(
            isinstance(a, ConnectionLostError) for a in args
        ):
            held.append(record)
            return False
        return True

    handlers = list(logging.getLogger().handlers)
    for handler in handlers:
        handler.addFilter(hold)
    lost = False
    try:
        yield
    except ConnectionLostError as exc:
        lost = True
        raise connection_lost_error(episode, exc) from None
    finally:
        for handler in handlers:
            handler.removeFilter(hold)
        if not lost:
            for record in dict.fromkeys(held):  # each record once, however many handlers
                logging.getLogger(record.name).handle(record)


def connection_lost_error(episode: Episode, exc: BaseException) -> CliError:
    """One line, status 1, for a simulator or robot that went away during ``episode``:
    when (simulated time, or run time on a real robot), whether a stop reached every
    robot's wheels, and what was lost (the error's own words)."""
    loop = episode.loop
    clock = "simulated" if loop.synchronous else "run"
    running = [
        name for name, adapter in episode.connection.adapters.items() if not adapter.wheels_stopped
    ]
    if running:
        names = ", ".join(repr(n) for n in running)
        wheels = f"no stop command reached {names}: check that it is not still driving"
        if len(running) > 1:
            wheels = f"no stop command reached {names}: check that they are not still driving"
    else:
        wheels = "the wheels were stopped"
    return CliError(
        f"the {episode.backend} connection was lost at t = {loop.time:.2f} s of {clock} time "
        f"and {wheels}. {first_line(exc)}",
        status=1,
    )
