"""Support shared by the remote API tests: servers on free loopback ports."""

from __future__ import annotations

import socket
from typing import Any

from puckboard.backends.coppeliasim.server.socket_loop import RemoteApiServer
from puckboard.scenario.scenefile import load_scene


def start_server(scene: str = "two-robot-pass", **options: Any) -> RemoteApiServer:
    return RemoteApiServer(load_scene(scene), host="127.0.0.1", port=0, **options).start()


def stop_server(server: RemoteApiServer) -> None:
    server.close()
    thread = server._thread
    assert thread is None or not thread.is_alive(), "server thread still running after close()"


def free_port() -> int:
    """A loopback port nobody listens on (bound, then released)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])
