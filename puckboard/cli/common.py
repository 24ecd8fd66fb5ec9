"""What every subcommand shares: its error type, argument checks and one-line messages.

Subcommand modules import from here, never from the package's ``__init__`` (which
imports them to build the parser), so nothing in the command line runs back up.
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import importlib
import logging
import math
import os
import re
import socket
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

from .._extras import missing_package_message

if TYPE_CHECKING:
    from ..control.episode import Episode

__all__ = [
    "CliError",
    "OneController",
    "VariationName",
    "add_variation_argument",
    "add_web_arguments",
    "bind_error_message",
    "check_host",
    "check_plot_file",
    "check_port",
    "check_seconds",
    "check_speed",
    "check_writable",
    "connection_loss_in_one_line",
    "connection_lost_error",
    "controller_error",
    "first_line",
    "help_text",
    "missing_extra",
    "require",
    "seed_type",
    "serve_until_interrupted",
    "start_web_view",
    "user_code_error",
    "web_url",
]


def help_text(docstring: str | None) -> str:
    """A module docstring as ``--help`` shows it: reST's ``double backticks`` become
    'quotes', which read as code in a terminal where backticks are noise."""
    return re.sub(r"``(.+?)``", r"'\1'", docstring or "", flags=re.S)


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


class _ArgumentError(CliError):
    """A value argparse refused in a subcommand's options (``prog`` is ``puckboard CMD``)."""

    def __init__(self, prog: str, message: str) -> None:
        super().__init__(message)
        self.prog = prog


class _StoreOnce(argparse._StoreAction):
    """An option of one value, refused when given twice (``--seed 7 --seed 8``): argparse
    would keep the last without a word, and which one was meant only the user knows."""

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: Any,
        option_string: str | None = None,
    ) -> None:
        given = vars(namespace).setdefault("_given_once", {})
        if option_string is not None and self.dest in given:
            shown = self.option_strings[-1]
            parser.error(f"{shown} given twice ({given[self.dest]}, then {values}); give it once")
        given[self.dest] = values
        setattr(namespace, self.dest, values)


class _SubcommandParser(argparse.ArgumentParser):
    """A subcommand's parser whose refusals end like every other bad input: one line
    ``puckboard CMD: error: ...`` and status 2 from :func:`main`, not argparse's usage
    block and ``SystemExit``; ``puckboard CMD --help`` still shows the usage. An option
    of one value given twice is refused (:class:`_StoreOnce`)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        # argument groups share these, so every plain option of the subcommand is one
        self.register("action", None, _StoreOnce)
        self.register("action", "store", _StoreOnce)
        # A value that starts with a minus and a digit ('--seeds -5:2', '--distance
        # -5mm') is a value, not an option: argparse alone takes only plain numbers
        # ('-5', '-0.5') so, and refuses the rest with "expected one argument", which
        # hides the check that would say what is wrong with the value. No option of
        # puckboard starts with a digit.
        self._negative_number_matcher = re.compile(r"^-\.?\d")

    def error(self, message: str) -> NoReturn:
        flag, sep, detail = message.partition(": ")
        if sep and flag.startswith("argument ") and detail.startswith(flag[9:] + " "):
            message = detail  # the type's message names the option already (seed_type)
        raise _ArgumentError(self.prog, message)


class OneController(argparse.Action):
    """``--controller`` of a command that runs one controller: given twice it is refused
    (argparse would keep the last and run it without a word), pointing to ``sweep``,
    which runs several side by side."""

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: Any,
        option_string: str | None = None,
    ) -> None:
        seen = "_controller_given"
        if getattr(namespace, seen, None) is not None:
            first = getattr(namespace, seen)
            parser.error(
                f"--controller given twice ({first}, then {values}); "
                f"{parser.prog} takes one controller: run it once per controller, or compare "
                f"them with puckboard sweep SCENE --controller {first} --controller {values}"
            )
        setattr(namespace, seen, values)
        setattr(namespace, self.dest, values)


# -- shared checks and messages ---------------------------------------------------------------
def seed_type(text: str) -> int:
    """argparse type of every ``--seed``: a whole number >= 0, which is what numpy's
    generators accept; without it ``--seed -1`` fails deep inside numpy with a message
    ("expected non-negative integer") that does not say which option was wrong."""
    try:
        seed = int(text)
    except ValueError:
        seed = -1
    if seed < 0:
        raise argparse.ArgumentTypeError(f"--seed must be a whole number ≥ 0, got {text}")
    return seed


def check_seconds(value: float | None, flag: str = "--duration") -> None:
    """Refuse a time option that is not a finite positive number of seconds. ``inf``
    passes a plain ``> 0`` test and then overflows when it is turned into a number of
    steps, and ``nan`` compares false with everything."""
    if value is not None and not (math.isfinite(value) and value > 0):
        raise CliError(f"{flag} must be a finite positive number of seconds, got {value:g}")


def check_speed(value: float | None, flag: str = "--speed") -> None:
    """Refuse a playback speed that is not a finite number ≥ 0 (0 = as fast as it goes)."""
    if value is not None and not (math.isfinite(value) and value >= 0):
        raise CliError(f"{flag} must be a finite number ≥ 0 (0 = unpaced), got {value}")


def check_port(port: int | None, flag: str = "--port", *, listen_on: str | None = None) -> None:
    """Refuse a TCP port that cannot be used, before any work: the one check of every
    port option.

    A port outside 0..65535 is refused for every use (the socket layer reports it as an
    ``OverflowError`` that names neither the option nor the range, and a client only
    after its connection timeout). With ``listen_on`` (the host a server of this
    command will listen on) the port is also bound and released at once, so a port in
    use or one that needs rights the user lacks is said now, in
    :func:`bind_error_message`'s words, and not by a traceback from a server started
    after the work (or from a child process, as ``docs --serve`` runs MkDocs).
    """
    if port is None:
        return
    if not 0 <= port <= 65535:
        raise CliError(f"{flag} must be 0..65535, got {port}")
    if listen_on is None or port == 0:
        return
    host = "" if listen_on == "*" else listen_on  # ZeroMQ's "every interface"
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    try:
        with socket.create_server((host, port), family=family):
            pass
    except OSError as exc:
        raise CliError(bind_error_message(exc, listen_on, port, flag)) from None


def check_host(host: str | None, flag: str = "--host", port_flag: str = "--port") -> None:
    """Refuse a host that carries a port (``127.0.0.1:38000``): the port is an option of
    its own, and the address with a port appended again names no machine."""
    if host is None or host.count(":") != 1:  # none, or an IPv6 address
        return
    name, _, port = host.partition(":")
    if port.isdigit():
        raise CliError(
            f"{flag} {host!r} holds a port; give it with {port_flag}: {flag} {name} "
            f"{port_flag} {port}"
        )


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


def require(module: str, what: str) -> None:
    """Import ``module`` now, so that a missing optional package is reported before a
    backend (perhaps a real robot) is opened and not halfway through a command."""
    try:
        importlib.import_module(module)
    except ImportError as exc:
        raise missing_extra(exc, what) from None


def check_plot_file(path: Path) -> None:
    """Refuse a ``--plot`` file matplotlib cannot write (its suffix) or cannot be drawn
    here (matplotlib missing), before any episode runs."""
    if path.suffix.lower() not in (".png", ".svg", ".pdf"):
        raise CliError(f"--plot {str(path)!r}: use a .png, .svg or .pdf file name")
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise CliError("--plot needs matplotlib: pip install 'puckboard[viz]'") from None


def check_writable(path: str | Path, flag: str, *, folder: bool = False) -> Path:
    """Refuse an output that cannot be written, before the run that would produce it:
    the one check of every output option (files and folders alike).

    Without this a read-only place, or a path through a regular file, is found out
    after a long run: the run is lost and the error is a traceback. ``path`` is a file to be written (its folder is
    created when missing) or, with ``folder=True``, a folder to write files in. Whether
    the folder takes files is tried by creating and removing a file in it, the one test
    that holds on every system and for every user (permission bits do not bind an
    administrator, and Windows has access lists besides).
    """
    import tempfile

    out = Path(path)
    where = out if folder else out.parent
    if not folder and out.is_dir():
        raise CliError(f"{flag} {str(out)!r} is a folder; give a file name")
    try:
        where.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(dir=where, prefix=".puckboard-", suffix=".probe")
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        reason = exc.strerror or str(exc)
        blocker = next((p for p in (where, *where.parents) if p.exists()), None)
        if blocker is not None and not blocker.is_dir():
            reason = f"{str(blocker)!r} is a file, not a folder"
        raise CliError(
            f"{flag} {str(out)!r}: cannot write in {str(where)!r} ({reason}); choose a "
            "folder you can write to"
        ) from None
    return out


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


def first_line(exc: BaseException) -> str:
    """The first line of ``exc``'s message (its type's name if it has none): what a
    one-line error shows of an exception whose message runs on."""
    text = str(exc).strip() or type(exc).__name__
    return text.splitlines()[0]


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


def _errnos(*names: str) -> frozenset[int]:
    """The error numbers called ``names`` on this system: POSIX names, and Windows'
    WSA* twins, which its socket errors carry instead."""
    return frozenset(
        code
        for name in names
        for mod in (errno, socket)
        if isinstance(code := getattr(mod, name, None), int)
    )


_IN_USE = _errnos("EADDRINUSE", "WSAEADDRINUSE")
_DENIED = _errnos("EACCES", "EPERM", "WSAEACCES")
#: The host is not an address of this machine, or no address at all: bind()'s own
#: errors, the one ZeroMQ gives for a host it cannot resolve (ENODEV), and the
#: resolver's (socket.create_server re-raises those as a plain OSError, and on some
#: systems their numbers overlap errno's: checked after _IN_USE and _DENIED).
_BAD_HOST = _errnos(
    "EADDRNOTAVAIL",
    "WSAEADDRNOTAVAIL",
    "ENODEV",
    "EINVAL",
    "EAFNOSUPPORT",
    "EAI_NONAME",
    "EAI_NODATA",
    "EAI_AGAIN",
    "EAI_FAIL",
)


def _bind_cause(exc: BaseException) -> BaseException:
    """The socket-level error behind ``exc``: servers wrap it in an error of their own
    (``raise OSError(...) from exc``), and only the original carries the errno."""
    seen: set[int] = set()
    current: BaseException | None = exc
    while current is not None and id(current) not in seen:
        if isinstance(current, socket.gaierror) or isinstance(getattr(current, "errno", None), int):
            return current
        seen.add(id(current))
        current = current.__cause__ or current.__context__
    return exc


def bind_error_message(exc: BaseException, host: str, port: int, flag: str = "--port") -> str:
    """Why listening on ``host:port`` failed, and what to do, for ``serve``, ``emulate``
    and the web view; ``flag`` is the option that chose the port.

    Blaming "another server using that port" for every failure sends a user after the
    wrong problem, so the three usual causes are told apart: the port is in use, the
    port needs rights the user lacks (below 1024 on most systems), or the host is not
    an address of this machine. Anything else keeps the system's reason.
    """
    cause = _bind_cause(exc)
    code = getattr(cause, "errno", None)
    where = f"cannot listen on {host}:{port}"
    bad_host = (
        f"{where}: {host!r} is not an address of this machine; use 127.0.0.1 (this machine "
        "only), 0.0.0.0 (every interface) or one of this machine's addresses"
    )
    if isinstance(cause, socket.gaierror):
        return bad_host
    if code in _IN_USE:
        return (
            f"{where}: the port is in use (by another server, or CoppeliaSim?); choose "
            f"another with {flag}, or {flag} 0 for any free one"
        )
    privileged = 0 < port < 1024
    if code in _DENIED:
        if privileged:
            return (
                f"{where}: permission denied; ports below 1024 need administrator rights, "
                f"use one from 1024 to 65535, e.g. {flag} 10000"
            )
        return f"{where}: permission denied by the system; choose another port with {flag}"
    if code in _BAD_HOST:
        return bad_host
    reason = getattr(cause, "strerror", None) or str(cause) or type(cause).__name__
    hint = f" (ports below 1024 need administrator rights; try {flag} 10000)" if privileged else ""
    return f"{where}: {reason}{hint}"


class VariationName(argparse.Action):
    """``--variation NAME``: a name of the variations' registry (an installed package's
    too), refused in one line otherwise; ``variation_given`` notes that it was given."""

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: Any,
        option_string: str | None = None,
    ) -> None:
        from ..scenario.variation import check_variation

        try:
            setattr(namespace, self.dest, check_variation(str(values)))
        except ValueError as exc:
            parser.error(f"--variation: {exc}")
        namespace.variation_given = True


def add_variation_argument(parser: argparse.ArgumentParser, seeded_by: str = "--seed") -> None:
    """``--variation NAME`` (the variations' registry, :mod:`puckboard.scenario.variation`),
    the same for ``run``, ``sweep``, ``tune`` and ``serve``; ``seeded_by`` is the option
    that seeds the draw (``sweep`` has ``--seeds``)."""
    from ..scenario.variation import NONE, VARIATIONS

    listed = "; ".join(f"{v.name}: {v.help}" for v in VARIATIONS.values() if v is not NONE)
    parser.add_argument(
        "--variation",
        action=VariationName,
        default=NONE.name,
        metavar="NAME",
        help=f"how each robot (and world) is drawn, seeded by {seeded_by}: {listed}; default "
        f"{NONE.name}: {NONE.help} (an installed package may add variations)",
    )


def add_web_arguments(parser: argparse.ArgumentParser, web_help: str | None = None) -> None:
    """``--web``, ``--web-host`` and ``--web-port``, the same for ``run``, ``serve`` and
    ``replay`` (``web_help`` says what ``--web`` serves, when not a live view)."""
    parser.add_argument(
        "--web", action="store_true",
        help=web_help
        or "also serve a live view of the simulation in the browser (needs puckboard[web])",
    )  # fmt: skip
    parser.add_argument(
        "--web-host", default="127.0.0.1", metavar="HOST",
        help="address of the web view (default 127.0.0.1, this machine only; 0.0.0.0 for a "
        "class)",
    )  # fmt: skip
    parser.add_argument(
        "--web-port", type=int, default=8080, metavar="PORT",
        help="port of the web view (default 8080; 0 = any free port)",
    )  # fmt: skip


def start_web_view(start: Any, args: argparse.Namespace) -> Any:
    """Start a web view with ``start()``; a missing aiohttp or a taken port is one line."""
    try:
        return start()
    except ImportError as exc:
        raise missing_extra(exc, "--web") from None
    except OSError as exc:
        raise CliError(
            bind_error_message(exc, args.web_host, args.web_port, "--web-port")
        ) from None


def web_url(view: Any, host: str) -> str:
    """The URL to share: on every interface, the machine's name stands in for 0.0.0.0."""
    if host in ("0.0.0.0", "*", "::"):
        return f"http://{socket.gethostname()}:{view.port}/  (or this machine's address)"
    return str(view.url)


def serve_until_interrupted(view: Any) -> None:
    """Keep a web view up (its page, its verdict) until Ctrl-C, then close it; the
    Ctrl-C goes on to :func:`puckboard.cli.main`, which ends the command with status 130
    as every command ends on Ctrl-C."""
    import time

    try:
        while True:
            time.sleep(0.5)
    finally:
        view.close()
