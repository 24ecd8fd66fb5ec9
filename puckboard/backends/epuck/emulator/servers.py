"""Byte servers for the emulator: a TCP listener and (POSIX only) a pseudo-terminal.

They move bytes between one client at a time and a protocol session
(:mod:`puckboard.backends.epuck.emulator.sessions`), in a background thread with short timeouts so
:meth:`stop` always returns promptly. Like the real robot, the emulator serves one
client at a time; when that client goes away its wheels are stopped and a new client
may connect.

For tests and demonstrations of failure handling, :meth:`inject` puts arbitrary bytes
on the line before the next reply, and :meth:`drop_client` cuts the connection. A
``reply_delay`` (seconds, asked again for every reply) holds each reply back, so a
client on this machine meets a slow link's timing (``puckboard emulate --link``).

TCP binds 127.0.0.1 unless told otherwise. Nothing a client sends is ever executed:
it is parsed as protocol bytes and anything else is skipped.
"""

from __future__ import annotations

import contextlib
import logging
import os
import select
import socket
import sys
import threading
import time
from collections.abc import Callable

from .sessions import Session

__all__ = ["PtyServer", "TcpServer", "pty_available"]

log = logging.getLogger(__name__)

SessionFactory = Callable[[], Session]


def pty_available() -> bool:
    """Pseudo-terminals exist on POSIX systems only (not on Windows)."""
    return os.name == "posix" and sys.platform != "win32"


class _ServerBase:
    def __init__(self, session_factory: SessionFactory, on_disconnect: Callable[[], None]) -> None:
        #: seconds to hold each reply back (None: none); ``sleep`` waits them out
        self.reply_delay: Callable[[], float] | None = None
        self.sleep: Callable[[float], None] = time.sleep
        self._session_factory = session_factory
        self._on_disconnect = on_disconnect
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._inject = bytearray()
        self._drop = threading.Event()
        self._lock = threading.Lock()
        self.clients = 0
        self.bytes_in = 0
        self.bytes_out = 0
        self.error: BaseException | None = None

    endpoint: str = ""

    def inject(self, data: bytes) -> None:
        """Send ``data`` to the client before the next reply (a fault for tests)."""
        with self._lock:
            self._inject += data

    def drop_client(self) -> None:
        """Cut the current client's connection (a fault for tests)."""
        self._drop.set()

    def _reply(self, session: Session, data: bytes) -> bytes:
        self.bytes_in += len(data)
        reply = session.feed(data)
        if reply and self.reply_delay is not None:
            self.sleep(self.reply_delay())  # the link's latency, as the client will time it
        if reply:
            with self._lock:
                if self._inject:
                    reply = bytes(self._inject) + reply
                    self._inject.clear()
        self.bytes_out += len(reply)
        return reply

    @property
    def started(self) -> bool:
        """Whether :meth:`start` has run (the server thread exists)."""
        return self._thread is not None

    def start(self) -> None:
        self._thread = threading.Thread(
            target=self._guarded_run, name=type(self).__name__, daemon=True
        )
        self._thread.start()

    def _guarded_run(self) -> None:
        try:
            self._run()
        except BaseException as exc:  # reported by the emulation, never silently lost
            self.error = exc
            log.exception("%s stopped with an error", type(self).__name__)

    def _run(self) -> None:  # pragma: no cover - overridden
        raise NotImplementedError

    def stop(self, timeout: float = 2.0) -> None:
        self._stop.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout)
        self._close()

    def _close(self) -> None:  # pragma: no cover - overridden
        pass

    def __enter__(self) -> _ServerBase:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()


class TcpServer(_ServerBase):
    """Serves the session over TCP on ``host:port`` (``port=0``: a free port)."""

    def __init__(
        self,
        session_factory: SessionFactory,
        on_disconnect: Callable[[], None],
        host: str = "127.0.0.1",
        port: int = 0,
    ) -> None:
        super().__init__(session_factory, on_disconnect)
        try:
            self._listener = socket.create_server((host, port))
        except OSError as exc:
            hint = (
                " (ports below 1024 need administrator rights; try --port 10000)"
                if 0 < port < 1024
                else ""
            )
            raise OSError(f"cannot listen on {host}:{port}: {exc}{hint}") from exc
        self._listener.settimeout(0.1)
        self.host, self.port = self._listener.getsockname()[:2]
        self.endpoint = f"{self.host}:{self.port}"
        self._conn: socket.socket | None = None

    def _run(self) -> None:
        while not self._stop.is_set():
            try:
                conn, peer = self._listener.accept()
            except TimeoutError:
                continue
            except OSError:
                if self._stop.is_set():
                    return
                raise
            self.clients += 1
            log.info("client %s:%s connected", *peer[:2])
            self._drop.clear()
            self._conn = conn
            try:
                self._serve(conn)
            finally:
                self._conn = None
                with contextlib.suppress(OSError):
                    conn.close()
                self._on_disconnect()
                log.info("client %s:%s gone", *peer[:2])

    def _serve(self, conn: socket.socket) -> None:
        conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        conn.settimeout(0.1)
        session = self._session_factory()
        while not self._stop.is_set() and not self._drop.is_set():
            try:
                data = conn.recv(65536)
            except TimeoutError:
                continue
            except OSError:
                return
            if not data:
                return
            reply = self._reply(session, data)
            if reply:
                try:
                    conn.sendall(reply)
                except OSError:
                    return

    def _close(self) -> None:
        with contextlib.suppress(OSError):
            self._listener.close()


class PtyServer(_ServerBase):
    """Serves the session on a pseudo-terminal; clients open :attr:`endpoint` (the
    slave device, e.g. ``/dev/pts/5``) like a serial port. POSIX only."""

    def __init__(self, session_factory: SessionFactory, on_disconnect: Callable[[], None]) -> None:
        if not pty_available():
            raise OSError(
                "pseudo-terminals are only available on Linux and macOS; serve sercom over "
                "TCP instead (puckboard emulate --protocol sercom --port 10001, then "
                "--device socket://127.0.0.1:10001), or use --protocol wifi"
            )
        import tty

        super().__init__(session_factory, on_disconnect)
        self._master, self._slave = os.openpty()
        tty.setraw(self._slave)  # no echo, no line editing: a clean 8-bit line
        self.endpoint = os.ttyname(self._slave)
        self.clients = 1

    def _run(self) -> None:
        session = self._session_factory()
        while not self._stop.is_set():
            if self._drop.is_set():
                # Hang up: closing the master makes every read on the slave fail.
                self._close()
                self._on_disconnect()
                return
            try:
                ready, _, _ = select.select([self._master], [], [], 0.1)
            except (OSError, ValueError):
                return
            if not ready:
                continue
            try:
                data = os.read(self._master, 65536)
            except OSError:
                return
            if not data:
                continue
            reply = self._reply(session, data)
            if reply:
                try:
                    os.write(self._master, reply)
                except OSError:
                    return

    def _close(self) -> None:
        for attr in ("_master", "_slave"):
            fd = getattr(self, attr, -1)
            if fd >= 0:
                with contextlib.suppress(OSError):
                    os.close(fd)
                setattr(self, attr, -1)
