"""Where an emulated robot is reached: its protocol served on TCP or a pseudo-terminal.

A real e-puck2 answers its Wi-Fi protocol on TCP and advanced sercom on a serial port;
the emulator offers the same two wires, so a client cannot tell it from a robot. This
module picks the server for a protocol and says how a client connects to it
(:class:`EndpointInfo`: the ``--backend`` and its options). What runs behind the wire
(the world, the judge, the scene's other robots) is the caller's business.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from .robot import EmulatedRobot
from .servers import PtyServer, TcpServer, _ServerBase, pty_available
from .sessions import SercomSession, WifiSession

__all__ = ["PROTOCOLS", "EndpointInfo", "open_endpoint"]

PROTOCOLS = ("wifi", "sercom")


@dataclass(frozen=True)
class EndpointInfo:
    """Where the emulated robot can be reached and how to connect to it."""

    protocol: str
    endpoint: str  # "127.0.0.1:10000" or "/dev/pts/5"
    backend: str  # --backend to use
    options: dict[str, Any]  # keyword options for the backend factory

    def command_line(self, scene: str) -> str:
        opts = " ".join(f"--{k} {v}" for k, v in self.options.items())
        return f"puckboard run {scene} --backend {self.backend} {opts}"


def open_endpoint(
    robot: EmulatedRobot,
    protocol: str,
    on_client_gone: Callable[[], None],
    *,
    host: str = "127.0.0.1",
    port: int = 0,
    serial: str | None = None,
) -> tuple[_ServerBase, EndpointInfo]:
    """A server (not yet started) for ``robot`` over ``protocol`` and how to reach it.

    ``protocol`` is ``"wifi"`` or ``"sercom"``; for sercom, ``serial`` is ``"pty"``
    (POSIX only) or ``"tcp"`` (pyserial's ``socket://`` URLs), default ``pty`` where
    there is one.
    """
    if protocol not in PROTOCOLS:
        raise ValueError(f"protocol must be one of {', '.join(PROTOCOLS)}, got {protocol!r}")
    server: _ServerBase
    if protocol == "wifi":
        server = TcpServer(lambda: WifiSession(robot), on_client_gone, host, port)
        info = EndpointInfo(
            protocol, server.endpoint, "epuck2-wifi", {"host": server.host, "port": server.port}
        )
        return server, info
    if serial is None:
        serial = "pty" if pty_available() else "tcp"
    if serial == "pty":
        server = PtyServer(lambda: SercomSession(robot), on_client_gone)
        device = server.endpoint
    elif serial == "tcp":
        server = TcpServer(lambda: SercomSession(robot), on_client_gone, host, port)
        device = f"socket://{server.endpoint}"
    else:
        raise ValueError(f"serial carrier must be 'pty' or 'tcp', got {serial!r}")
    return server, EndpointInfo(protocol, server.endpoint, "sercom", {"device": device})
