"""The checks of a value a user gives on the command line, made before any work: a
seed, a time, a speed, a port or host, a file to write, an optional package."""

from __future__ import annotations

import argparse
import importlib
import math
import os
import socket
from pathlib import Path

from .bind import bind_error_message
from .errors import CliError, missing_extra

__all__ = [
    "check_host",
    "check_plot_file",
    "check_port",
    "check_seconds",
    "check_speed",
    "check_writable",
    "require",
    "seed_type",
]


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
    after a long run: the run is lost and the error is a traceback. ``path`` is a file
    to be written (its folder is created when missing) or, with ``folder=True``, a
    folder to write files in. Whether the folder takes files is tried by creating and
    removing a file in it, the one test that holds on every system and for every user
    (permission bits do not bind an administrator, and Windows has access lists
    besides).
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
