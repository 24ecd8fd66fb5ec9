"""RemoteLink: one connection to a ZeroMQ remote API server, with a deadline on every call.

The official client ``coppeliasim-zmqremoteapi-client`` (2.0.x, imported only here) waits
forever for an answer. Here its socket gets a receive/send timeout (``timeout``, default
5 s), no linger and relaxed REQ semantics, so a dead or vanished server raises
:class:`~puckboard.errors.ConnectionLostError` within the timeout, and a later call (the
wheel stop on close) can still try once.

Robots of one process share a link: one socket, one lock (the source framework's
``synchronized (lockAPI)``, §5.1.4), so a sensing thread and the controller never
overlap on the wire.
"""

from __future__ import annotations

import contextlib
import logging
import sys
import threading
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from ...errors import AdapterError, ConnectionLostError

if TYPE_CHECKING:
    from coppeliasim_zmqremoteapi_client import RemoteAPIClient

__all__ = ["DEFAULT_PORT", "RemoteLink"]

log = logging.getLogger(__name__)

#: CoppeliaSim's default remote API port.
DEFAULT_PORT = 23000
_LOST_RETRY_TIMEOUT = 0.5  # s: the one last try (wheel stop) after the connection was lost


class RemoteLink:
    """One connection to a remote API server, shared by every robot of a process.

    Wraps the official client: every call holds :attr:`lock` and fails within
    ``timeout`` seconds. Server-side errors (``{err: ...}``) become
    :class:`~puckboard.errors.AdapterError` naming the function; silence becomes
    :class:`~puckboard.errors.ConnectionLostError`, after which the link is *lost*:
    further calls fail at once, except a ``last_try`` (used to stop the wheels).
    """

    def __init__(self, host: str = "127.0.0.1", port: int = DEFAULT_PORT, timeout: float = 5.0):
        if not timeout > 0:
            raise ValueError(f"timeout must be positive seconds, got {timeout}")
        try:
            import zmq
            from coppeliasim_zmqremoteapi_client import RemoteAPIClient
        except ImportError as exc:
            raise ImportError(
                f"the CoppeliaSim backend needs a missing package ({exc.name}); "
                "install it with: pip install 'puckboard[coppeliasim]'"
            ) from exc
        self._zmq = zmq
        self.host = host
        self.port = port
        self.timeout = float(timeout)
        self.lock = threading.RLock()
        self.lost: str | None = None
        self._gave_up = False
        self.closed = False
        self.client = RemoteAPIClient(host, port)
        _drop_main_require(self.client)
        self._set_timeout(self.timeout)
        sock = self.client.socket
        sock.setsockopt(zmq.LINGER, 0)
        # after a timeout a strict REQ socket refuses to send again; relaxed + correlated
        # lets the next request go out and discards a late reply to the old one
        sock.setsockopt(zmq.REQ_RELAXED, 1)
        sock.setsockopt(zmq.REQ_CORRELATE, 1)
        try:
            self.call("zmqRemoteApi.require", ["sim"])
            info = self.call("zmqRemoteApi.info", ["sim"])
        except BaseException:
            self.close()
            raise
        if not isinstance(info, dict):
            self.close()
            raise AdapterError(f"{self.endpoint} answered zmqRemoteApi.info with {info!r}")
        #: Served ``sim`` function names (without the ``sim.`` prefix) and constants.
        self.functions = frozenset(
            k for k, v in info.items() if isinstance(v, dict) and "func" in v
        )
        self.constants = {
            k: v["const"] for k, v in info.items() if isinstance(v, dict) and "const" in v
        }
        #: The official client's ``sim`` object, for calls this adapter does not wrap.
        self.sim = self.client.getObject("sim", _info=info)

    @property
    def endpoint(self) -> str:
        return f"tcp://{self.host}:{self.port}"

    def _set_timeout(self, seconds: float) -> None:
        ms = max(1, int(seconds * 1000))
        self.client.socket.setsockopt(self._zmq.RCVTIMEO, ms)
        self.client.socket.setsockopt(self._zmq.SNDTIMEO, ms)

    def has(self, function: str) -> bool:
        return function.removeprefix("sim.") in self.functions

    def call(self, func: str, args: Sequence[Any] = (), *, last_try: bool = False) -> Any:
        """Call ``func`` with ``args``; see the class docstring for the errors."""
        zmq = self._zmq
        with self.lock:
            if self.closed:
                raise ConnectionLostError(f"connection to {self.endpoint} is closed")
            retrying = self.lost is not None
            if retrying:
                if not last_try or self._gave_up:
                    raise ConnectionLostError(self.lost)
                self._set_timeout(min(self.timeout, _LOST_RETRY_TIMEOUT))
            try:
                result = self.client.call(func, list(args))
                if retrying:
                    log.info("the remote API at %s answers again", self.endpoint)
                    self.lost = None
                return result
            except zmq.Again:
                self._gave_up = retrying
                self.lost = (
                    f"no answer from the remote API at {self.endpoint} within "
                    f"{self.timeout:g} s (calling {func}). Is CoppeliaSim running with its ZMQ "
                    "remote API add-on enabled, or `puckboard serve` on that port?"
                )
                raise ConnectionLostError(self.lost) from None
            except zmq.ZMQError as exc:
                self.lost = f"connection to {self.endpoint} failed calling {func}: {exc}"
                raise ConnectionLostError(self.lost) from None
            except KeyError as exc:
                raise AdapterError(
                    f"{func}: the server at {self.endpoint} answered without {exc}; it may "
                    "speak remote API protocol 1 (CoppeliaSim ≤ 4.5), which this client does not"
                ) from None
            except Exception as exc:
                if type(exc) is Exception:  # the client's way of raising an `err` reply
                    raise AdapterError(f"{func}: {exc}") from None
                raise AdapterError(
                    f"{func}: unreadable reply ({type(exc).__name__}: {exc})"
                ) from exc
            finally:
                if retrying:
                    self._set_timeout(self.timeout)

    def close(self) -> None:
        """Close the socket (no linger) and its context. Idempotent."""
        with self.lock:
            if self.closed:
                return
            self.closed = True
            try:
                self.client.socket.close(0)
                self.client.context.term()
            except Exception as exc:  # pragma: no cover - best effort
                log.debug("closing the remote API client: %s", exc)


def _drop_main_require(client: RemoteAPIClient) -> None:
    """The client stores its ``require`` in ``__main__``; remove it so the client (and its
    socket) is not kept alive by a global after the adapter is closed."""
    main = sys.modules.get("__main__")
    fn = getattr(main, "require", None)
    if fn is not None and getattr(fn, "__self__", None) is client:
        with contextlib.suppress(AttributeError):
            delattr(main, "require")
