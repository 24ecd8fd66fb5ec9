"""Fixtures: a ``puckboard serve`` on a free loopback port, always shut down, and clients.

Every server runs in a daemon thread of the test process and is closed by the fixture
whatever the test does; the fixture then checks the server thread has really ended, so
no test leaves a thread (or a bound port) behind.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

pytest.importorskip("zmq")
pytest.importorskip("cbor2")
pytest.importorskip("coppeliasim_zmqremoteapi_client")

from coppeliasim_support import start_server, stop_server

from puckboard.backends.coppeliasim.server.socket_loop import RemoteApiServer

pytestmark = pytest.mark.network


@pytest.fixture
def server() -> Iterator[RemoteApiServer]:
    srv = start_server()
    try:
        yield srv
    finally:
        stop_server(srv)


@pytest.fixture
def make_client(server: RemoteApiServer) -> Iterator[Any]:
    """Official clients connected to ``server``, with a receive timeout so a test never hangs."""
    import zmq
    from coppeliasim_zmqremoteapi_client import RemoteAPIClient

    made: list[Any] = []

    def make() -> Any:
        client = RemoteAPIClient("127.0.0.1", server.port)
        client.socket.setsockopt(zmq.RCVTIMEO, 5000)
        client.socket.setsockopt(zmq.LINGER, 0)
        made.append(client)
        return client

    yield make
    for client in made:
        client.socket.close(0)
