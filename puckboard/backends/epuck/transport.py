"""Byte pipes to the robot: TCP for Wi-Fi, a serial port for Bluetooth/USB.

Both offer the same four calls, all bounded in time, so nothing above them can hang:

* ``write(data)``;
* ``read_exact(n, timeout)``: exactly ``n`` bytes or :class:`TransportTimeout` (a
  :class:`~puckboard.errors.ConnectionLostError`) when they do not come in time;
* ``drain(quiet)``: discard whatever arrives until the line has been quiet for
  ``quiet`` seconds (never longer than a second overall) — the first step of
  resynchronising after garbage;
* ``close()``.

A peer that closes the connection, a serial device that disappears, or an OS error
becomes :class:`~puckboard.errors.ConnectionLostError` with a message that says what
was lost and where. pyserial is imported only when a serial port is opened, and its
absence is reported with the extra to install.
"""

from __future__ import annotations

import contextlib
import logging
import socket
import time
from typing import Any, Protocol

from ...errors import ConnectionLostError

__all__ = ["SerialTransport", "TcpTransport", "Transport", "TransportTimeout"]

log = logging.getLogger(__name__)

_MAX_DRAIN_S = 1.0


class TransportTimeout(ConnectionLostError):
    """The robot did not send the expected bytes in time (it may still be there)."""


class Transport(Protocol):
    description: str

    def write(self, data: bytes) -> None: ...

    def read_exact(self, n: int, timeout: float) -> bytes: ...

    def drain(self, quiet: float = 0.05) -> int: ...

    def discard_pending(self) -> int: ...

    def close(self) -> None: ...


class _ByteStream:
    """What both transports share: reading exactly ``n`` bytes before a deadline, and
    dropping whatever arrives until the line goes quiet.

    Subclasses provide ``_recv(n, timeout)``, which returns what arrived (possibly
    nothing) within ``timeout`` and raises :class:`ConnectionLostError` when the link is
    gone, and ``_check_open``.
    """

    description: str

    def _check_open(self) -> None:
        raise NotImplementedError

    def _recv(self, n: int, timeout: float) -> bytes:
        raise NotImplementedError

    def read_exact(self, n: int, timeout: float) -> bytes:
        """Exactly ``n`` bytes, or :class:`TransportTimeout` after ``timeout`` seconds."""
        self._check_open()
        deadline = time.monotonic() + timeout
        buf = bytearray()
        while len(buf) < n:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise TransportTimeout(
                    f"the robot ({self.description}) sent {len(buf)} of {n} expected bytes "
                    f"within {timeout:.2f} s"
                )
            buf += self._recv(n - len(buf), remaining)
        return bytes(buf)

    def drain(self, quiet: float = 0.05) -> int:
        """Read and drop bytes until none arrive for ``quiet`` seconds (giving up after
        ``_MAX_DRAIN_S``, for a robot that never stops talking); return how many."""
        self._check_open()
        dropped = 0
        end = time.monotonic() + _MAX_DRAIN_S
        while time.monotonic() < end:
            chunk = self._recv(65536, quiet)
            if not chunk:
                break
            dropped += len(chunk)
        return dropped


class TcpTransport(_ByteStream):
    """A TCP connection (the e-puck2's Wi-Fi server listens on port 1000)."""

    def __init__(self, host: str, port: int, *, connect_timeout: float = 5.0) -> None:
        self.description = f"tcp://{host}:{port}"
        try:
            self._sock = socket.create_connection((host, port), timeout=connect_timeout)
        except OSError as exc:
            raise ConnectionLostError(
                f"could not connect to the robot at {host}:{port} ({exc}); check that it is "
                "on, its selector is at 15 with the Wi-Fi firmware, and you are on its network"
            ) from exc
        self._sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self._closed = False

    def write(self, data: bytes) -> None:
        self._check_open()
        try:
            self._sock.settimeout(5.0)
            self._sock.sendall(data)
        except OSError as exc:
            raise ConnectionLostError(
                f"sending to the robot at {self.description} failed: {exc}"
            ) from exc

    def _recv(self, n: int, timeout: float) -> bytes:
        self._sock.settimeout(timeout)
        try:
            chunk = self._sock.recv(n)
        except TimeoutError:
            return b""
        except OSError as exc:
            raise ConnectionLostError(
                f"connection to the robot at {self.description} failed: {exc}"
            ) from exc
        if not chunk:
            raise ConnectionLostError(f"the robot at {self.description} closed the connection")
        return chunk

    def discard_pending(self) -> int:
        """Discard bytes that have already arrived, without waiting; return how many."""
        self._check_open()
        dropped = 0
        self._sock.setblocking(False)
        try:
            while True:
                try:
                    chunk = self._sock.recv(65536)
                except (BlockingIOError, InterruptedError):
                    break
                except OSError as exc:
                    raise ConnectionLostError(
                        f"connection to the robot at {self.description} failed: {exc}"
                    ) from exc
                if not chunk:
                    raise ConnectionLostError(
                        f"the robot at {self.description} closed the connection"
                    )
                dropped += len(chunk)
        finally:
            self._sock.setblocking(True)
        return dropped

    def close(self) -> None:
        if self._closed:
            return
        self._closed = True
        with contextlib.suppress(OSError):
            self._sock.shutdown(socket.SHUT_RDWR)
        self._sock.close()

    def _check_open(self) -> None:
        if self._closed:
            raise ConnectionLostError(f"the connection {self.description} is closed")


class SerialTransport(_ByteStream):
    """A serial port through pyserial: ``/dev/rfcomm0``, ``/dev/ttyACM0``, ``COM5``, a
    pseudo-terminal, or any pyserial URL (``loop://``, ``socket://host:port``)."""

    def __init__(self, device: str, *, baudrate: int = 115200) -> None:
        serial = import_pyserial()
        self.description = device
        try:
            self._port: Any = serial.serial_for_url(device, baudrate=baudrate, timeout=0.1)
        except (serial.SerialException, OSError, ValueError) as exc:
            raise ConnectionLostError(
                f"could not open the serial device {device!r} ({exc}); on Linux bind the robot "
                "with `sudo rfcomm bind 0 <MAC> 1` (e-puck1) or channel 2 (e-puck2) and use "
                "/dev/rfcomm0; on Windows use the outgoing COM port of the paired robot"
            ) from exc
        self._errors: tuple[type[BaseException], ...] = (serial.SerialException, OSError)
        self._closed = False

    def write(self, data: bytes) -> None:
        self._check_open()
        try:
            self._port.write_timeout = 5.0
            self._port.write(data)
            self._port.flush()
        except self._errors as exc:
            raise ConnectionLostError(f"writing to {self.description} failed: {exc}") from exc

    def _recv(self, n: int, timeout: float) -> bytes:
        try:
            self._port.timeout = min(timeout, 0.2)
            return bytes(self._port.read(n))
        except self._errors as exc:
            raise ConnectionLostError(
                f"reading from {self.description} failed (robot off or out of range?): {exc}"
            ) from exc

    def discard_pending(self) -> int:
        """Discard bytes that have already arrived, without waiting; return how many."""
        self._check_open()
        try:
            waiting = int(self._port.in_waiting)
            if waiting:
                self._port.timeout = 0
                return len(self._port.read(waiting))
        except self._errors as exc:
            raise ConnectionLostError(f"reading from {self.description} failed: {exc}") from exc
        return 0

    def close(self) -> None:
        if self._closed:
            return
        self._closed = True
        try:
            self._port.close()
        except self._errors as exc:
            log.debug("closing %s: %s", self.description, exc)

    def _check_open(self) -> None:
        if self._closed:
            raise ConnectionLostError(f"the serial device {self.description} is closed")


def import_pyserial() -> Any:
    """pyserial, or an ImportError that says how to install it."""
    try:
        import serial
    except ImportError as exc:
        raise ImportError(
            "the sercom backend needs pyserial; install it with: pip install 'puckboard[real]'"
        ) from exc
    return serial
