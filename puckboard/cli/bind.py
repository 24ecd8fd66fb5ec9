"""Why a server could not listen, in words that point to the fix: ``serve``, ``emulate``,
``docs --serve`` and the web view say it alike."""

from __future__ import annotations

import errno
import socket

__all__ = ["bind_error_message"]


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
