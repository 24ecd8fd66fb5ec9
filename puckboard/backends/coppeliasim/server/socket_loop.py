"""The ZeroMQ side of ``puckboard serve``: one socket, one thread, many clients.

The official client opens a REQ socket; CoppeliaSim answers with a REP socket. We bind a
ROUTER socket instead, which is wire-compatible with REQ peers and lets the server hold
a reply back: a client waiting in ``sim.step`` for the others gets its answer when the
simulation has advanced, without a busy loop. While it waits it is sent a ``_*wait*_``
heartbeat every ``heartbeat`` seconds (it answers ``_*executed*_``), as CoppeliaSim's
own server does, so its receive timeout never fires while the server is alive.

Everything — decoding, the world, the clients — lives in the server thread; the only
thing other threads touch is the stop flag. Whatever arrives (random bytes, a CBOR
bomb, a multi-part message from a non-REQ peer, a request with wrong argument types),
the answer is an ``err`` reply or silence, never an exception out of the loop.

When the simulation runs and no client steps it, it advances in real time, like
CoppeliaSim's free-running mode.

A class of stepping clients can freeze for a reason no student sees: one client's
loop ended and left while it was still stepping, and everybody waits for it until its
idle timeout. When stepping clients have waited ``stall_warning`` seconds for a client,
the server logs a warning naming that client (its short id, as the log and the web view
show it) and what it last did, once per client.
"""

from __future__ import annotations

import logging
import math
import threading
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import zmq

from ....profile import get_profile
from .api.state import STEP_PENDING, ApiError
from .clients import ClientState, ClientTable
from .codec import (
    END,
    EXECUTED,
    MAX_FRAME_BYTES,
    FrameError,
    decode_request,
    encode_reply,
    error_reply,
    return_reply,
    wait_reply,
)
from .simapi import SimApi
from .view import ServedView

if TYPE_CHECKING:
    from ....scenario.scene import Scene

__all__ = ["DEFAULT_PORT", "RemoteApiServer", "serve_scene"]

log = logging.getLogger(__name__)

#: CoppeliaSim's default remote API port.
DEFAULT_PORT = 23000
_EMPTY = b""
_RET_NONE = return_reply([])
_MODULES = ("sim",)
#: How often step observers hear from a simulation that stands still (s).
_STILL_NOTIFY_S = 0.25


class RemoteApiServer:
    """Serves ``scene`` over the ZeroMQ remote API; see the module docstring.

    ``port=0`` picks a free port (read it from :attr:`port`). ``start()`` serves in a
    background thread; ``serve_forever()`` in the calling thread (Ctrl-C ends it). The
    server stands in for CoppeliaSim, so its robots are V-REP's e-puck model
    (``epuck-vrep``) unless ``profile`` names another (``None`` keeps the scene's).
    ``script_functions=False`` leaves puckboard's sense-all and set-wheels functions out
    of the e-puck's script, as in a CoppeliaSim whose model lacks them.
    ``stepping_timeout=None`` (CoppeliaSim's behaviour) lets a silent stepping client hold
    the simulation until its idle timeout (``max_idle`` at most); a number frees the
    others after that many silent seconds. ``stall_warning`` is how long stepping clients
    wait for another before the server names it in a warning.
    """

    def __init__(
        self,
        scene: Scene,
        *,
        host: str = "127.0.0.1",
        port: int = DEFAULT_PORT,
        seed: int = 0,
        model: str = "ePuck",
        stepping_timeout: float | None = None,
        max_idle: float = 600.0,
        heartbeat: float = 0.25,
        stall_warning: float = 5.0,
        realtime: bool = True,
        profile: str | None = "epuck-vrep",
        script_functions: bool = True,
    ) -> None:
        if heartbeat <= 0 or stall_warning <= 0:
            raise ValueError(
                f"heartbeat and stall_warning must be positive seconds, got {heartbeat} and "
                f"{stall_warning}"
            )
        if profile is not None:
            scene = scene.with_profile(get_profile(profile).name)
        self.api = SimApi(
            scene, seed=seed, model=model, realtime=realtime, script_functions=script_functions
        )
        self.clients = ClientTable(stepping_timeout=stepping_timeout, max_idle=max_idle)
        self.host = host
        self.heartbeat = heartbeat
        self.stall_warning = stall_warning
        self.realtime = realtime
        self.requests = 0
        self.errors = 0
        self._context = zmq.Context()
        self._socket = self._context.socket(zmq.ROUTER)
        self._socket.setsockopt(zmq.LINGER, 0)
        self._socket.setsockopt(zmq.MAXMSGSIZE, MAX_FRAME_BYTES + 1024)
        endpoint_host = {"0.0.0.0": "*", "localhost": "127.0.0.1"}.get(host, host)
        try:
            if port == 0:
                self.port = self._socket.bind_to_random_port(f"tcp://{endpoint_host}")
            else:
                self._socket.bind(f"tcp://{endpoint_host}:{port}")
                self.port = port
        except zmq.ZMQError as exc:
            self._socket.close(0)
            self._context.term()
            # only a port in use has another server to blame; the cause keeps the errno
            # so callers (puckboard serve) can tell no rights and a wrong host apart
            hint = (
                " Is another server (or CoppeliaSim) using that port? Choose another port."
                if exc.errno == zmq.EADDRINUSE
                else ""
            )
            raise OSError(f"cannot serve on {host}:{port}: {exc}.{hint}") from exc
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._closed = False
        self._next_free_step = 0.0
        #: When the stepping clients last saw progress (a step, a start, a new stepper).
        self._progress_at = 0.0
        self._free_running = False
        self._observers: list[Callable[[RemoteApiServer], None]] = []
        self._last_notified = -math.inf

    # -- observers ---------------------------------------------------------------------------
    def add_step_observer(self, observer: Callable[[RemoteApiServer], None]) -> None:
        """Call ``observer(server)`` in the server thread after every simulation step, and
        about four times a second while the simulation stands still (stopped, or waiting
        for a stepping client), so a viewer also sees a scene nobody has started.

        The observer runs in the server's thread, between requests, so it may read the
        world and the client table without a lock; it must return quickly (copy what it
        needs and hand it to its own thread). An exception in it is logged and the
        observer is kept.
        """
        self._observers.append(observer)

    def view(self) -> ServedView:
        """What this server serves, read-only and typed: what a watcher (the web view)
        reads instead of the server's internals."""
        return ServedView(self.api, self.clients)

    def _notify(self, now: float) -> None:
        self._last_notified = now
        for observer in self._observers:
            try:
                observer(self)
            except Exception:
                log.exception("step observer %r failed; the server keeps serving", observer)

    # -- lifecycle ---------------------------------------------------------------------------
    @property
    def address(self) -> str:
        return f"tcp://{self.host}:{self.port}"

    def start(self) -> RemoteApiServer:
        """Serve in a daemon thread; returns ``self``."""
        if self._thread is not None:
            raise RuntimeError("server already started")
        self._thread = threading.Thread(
            target=self._run, name=f"remote-api:{self.port}", daemon=True
        )
        self._thread.start()
        return self

    def serve_forever(self) -> None:
        """Serve in the calling thread until :meth:`close` (from another thread) or Ctrl-C."""
        self._run()

    def close(self, timeout: float = 5.0) -> None:
        """Stop serving and release the port. Idempotent."""
        self._stop.set()
        thread = self._thread
        if thread is not None and thread is not threading.current_thread():
            thread.join(timeout)
            if thread.is_alive():  # pragma: no cover - the loop polls every 50 ms
                log.warning("remote API server thread did not stop within %.1f s", timeout)
                return
        if not self._closed:
            self._closed = True
            self._socket.close(0)
            self._context.term()

    def __enter__(self) -> RemoteApiServer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- the loop ----------------------------------------------------------------------------
    def _run(self) -> None:
        sock = self._socket
        try:
            while not self._stop.is_set():
                if sock.poll(self._poll_timeout_ms(), zmq.POLLIN):
                    for _ in range(256):  # a burst, then housekeeping
                        try:
                            frames = sock.recv_multipart(zmq.NOBLOCK)
                        except zmq.Again:
                            break
                        self._handle_safely(frames)
                try:
                    self._housekeeping(time.monotonic())
                except Exception:  # a failing step must not end the server either
                    self.errors += 1
                    log.exception("simulation step failed; the server keeps serving")
        except zmq.ContextTerminated:  # pragma: no cover - close() from another thread
            pass
        finally:
            self._stop.set()

    def _poll_timeout_ms(self) -> int:
        timeout = 50.0
        if self._free_running:
            timeout = min(timeout, max(0.0, (self._next_free_step - time.monotonic()) * 1e3))
        return int(timeout)

    def _handle_safely(self, frames: list[bytes]) -> None:
        try:
            self._handle(frames)
        except Exception:  # never let one message end the server
            self.errors += 1
            log.exception("unexpected error while handling a request; the server keeps serving")

    def _send(self, envelope: list[bytes], payload: bytes) -> None:
        try:
            self._socket.send_multipart([*envelope, payload], zmq.NOBLOCK)
        except zmq.ZMQError as exc:  # peer gone or its queue full: drop the reply
            log.debug("reply dropped: %s", exc)

    def _handle(self, frames: list[bytes]) -> None:
        if len(frames) < 2:
            return  # an identity with nothing in it
        try:
            delimiter = frames.index(_EMPTY, 1)
        except ValueError:  # a DEALER/raw peer without REQ's empty delimiter
            envelope, body = frames[:1], frames[1:]
        else:
            envelope, body = frames[: delimiter + 1], frames[delimiter + 1 :]
        self.requests += 1
        if len(body) != 1:
            self.errors += 1
            self._send(envelope, error_reply(f"expected one CBOR frame, got {len(body)} frames"))
            return
        try:
            req = decode_request(body[0])
        except FrameError as exc:
            self.errors += 1
            log.debug("malformed request: %s", exc)
            self._send(envelope, error_reply(str(exc), legacy=exc.legacy))
            return
        now = time.monotonic()
        client, new = self.clients.touch(req.uuid, now, lang=req.lang, timeout=req.timeout)
        if new:
            log.info(
                "client %s connected (%s client, protocol %s)",
                client.short, req.lang or "unknown", req.ver if req.ver is not None else "?",
            )  # fmt: skip
        client.parked = None  # a new request makes any held envelope stale
        func = req.func
        if func != EXECUTED:
            # a REQ client only sends anew once it gave up waiting (or was answered)
            client.waiting = False
            client.released = False
        if func == EXECUTED:
            self._executed(client, envelope, now)
        elif func == END:
            self._forget(client, "said goodbye")
            self._send(envelope, encode_reply({}))
        elif func == "zmqRemoteApi.require":
            self._send(envelope, self._require(req.args, info=False))
        elif func == "zmqRemoteApi.info":
            self._send(envelope, self._require(req.args, info=True))
        else:
            self._call(client, envelope, func, req.args, now)

    def _require(self, args: list[Any], *, info: bool) -> bytes:
        name = args[0] if args else None
        if not isinstance(name, str):
            return error_reply("zmqRemoteApi.require: expected a module name such as 'sim'")
        module = name.split("-", 1)[0]  # 'sim-2' (versioned require) is 'sim'
        if module not in _MODULES:
            return error_reply(
                f"module {name!r} is not served; this server serves: {', '.join(_MODULES)}"
            )
        return return_reply([self.api.info()] if info else [])

    def _call(
        self, client: ClientState, envelope: list[bytes], func: str, args: list[Any], now: float
    ) -> None:
        client.last_call = func
        client.last_call_at = now
        try:
            result = self.api.call(client, func, args)
        except ApiError as exc:
            self.errors += 1
            self._send(envelope, error_reply(str(exc)))
            return
        except Exception as exc:
            self.errors += 1
            log.exception("%s failed", func)
            self._send(envelope, error_reply(f"{func} failed: {type(exc).__name__}: {exc}"))
            return
        if result is STEP_PENDING:
            client.wait_since = now
            self._pump(now)
            if client.waiting:
                self._send(envelope, wait_reply())
            else:  # this very call completed the gate: the step is done already
                client.released = False
                self._send(envelope, _RET_NONE)
            return
        self._send(envelope, return_reply(result) if result else _RET_NONE)
        if func == "sim.stopSimulation":
            for waiting in self.clients.reset_stepping():
                self._finish(waiting)
        elif func in ("sim.setStepping", "sim.startSimulation"):
            self._next_free_step = now
            self._progress_at = now
            self._pump(now)

    def _executed(self, client: ClientState, envelope: list[bytes], now: float) -> None:
        if client.released:  # the step finished between our _*wait*_ and this answer
            client.released = False
            self._send(envelope, _RET_NONE)
        elif not client.waiting:
            self._send(envelope, error_reply("_*executed*_ received, but no call is waiting"))
        elif not self.api.advancing or client.desired_step <= self.api.step_count:
            client.waiting = False
            self._send(envelope, _RET_NONE)
        else:
            client.parked = envelope
            client.parked_since = now

    def _finish(self, client: ClientState) -> None:
        """The step ``client`` waited for is done (or the simulation stopped): answer it."""
        client.waiting = False
        if client.parked is not None:
            self._send(client.parked, _RET_NONE)
            client.parked = None
        else:  # its _*executed*_ is still on the way
            client.released = True

    def _pump(self, now: float) -> None:
        """Advance while every gating client has asked for the next step."""
        api = self.api
        while api.advancing and self.clients.gate_open(api.step_count, now):
            self._advance(now)

    def _advance(self, now: float) -> None:
        """One step; then answer every client whose awaited step it was."""
        self.api.advance()
        self._progress_at = now
        if self._observers:
            self._notify(now)
        for client in self.clients.done_waiting(self.api.step_count):
            self._finish(client)

    def _forget(self, client: ClientState, why: str) -> None:
        self.clients.forget(client.uuid)
        for robot in sorted(client.robots):
            self.api.stop_robot(robot)
        stopped = ", ".join(self.api.objects.bases[r].name for r in sorted(client.robots))
        log.info("client %s %s%s", client.short, why, f"; stopped {stopped}" if stopped else "")

    def _housekeeping(self, now: float) -> None:
        for client in self.clients:
            if client.parked is not None and now - client.parked_since >= self.heartbeat:
                self._send(client.parked, wait_reply())  # still waiting: keep it alive
                client.parked = None
        for client in self.clients.expired(now):
            self._forget_expired(client)
        api = self.api
        self._free_running = False
        if self._observers and now - self._last_notified >= _STILL_NOTIFY_S:
            self._notify(now)
        if not api.advancing:
            return
        gating = self.clients.gating(now)
        if gating:
            self._pump(now)  # a silent client may just have stopped gating
            self._next_free_step = now
            self._warn_of_holders(gating, now)
        elif self.realtime:
            self._free_running = True
            if now >= self._next_free_step:
                self._advance(now)
                self._next_free_step += api.world.dt
                if now - self._next_free_step > 1.0:  # fell behind: do not race to catch up
                    self._next_free_step = now + api.world.dt

    def _warn_of_holders(self, gating: list[ClientState], now: float) -> None:
        """Name, once, each stepping client the others have waited for too long."""
        waiting = [c for c in gating if c.waiting]
        if not waiting:
            return
        since = max(min(c.wait_since for c in waiting), self._progress_at)
        if now - since < self.stall_warning:
            return
        for holder in gating:
            if holder.waiting or holder.warned_holding:
                continue
            holder.warned_holding = True
            if self.clients.stepping_timeout is None:
                way_out = (
                    "puckboard serve --stepping-timeout S frees the others after S silent seconds"
                )
            else:
                way_out = (
                    f"--stepping-timeout frees the others once it has been silent for "
                    f"{self.clients.stepping_timeout:g} s"
                )
            last = (
                f"its last call was {holder.last_call}, {now - holder.last_call_at:.1f} s ago"
                if holder.last_call
                else "it has called no sim function"
            )
            log.warning(
                "%s waited %.1f s in sim.step for client %s, which has not asked for the next "
                "step; %s (%d sim.step calls, %d of them while the simulation was not "
                "running). A stepping client that ended its loop without "
                "sim.setStepping(False), crashed or sits at a breakpoint holds everybody back "
                "until its idle timeout (%.0f s); %s",
                "1 stepping client has" if len(waiting) == 1
                else f"{len(waiting)} stepping clients have",
                now - since, holder.short, last, holder.steps, holder.idle_steps,
                holder.idle_timeout, way_out,
            )  # fmt: skip

    def _forget_expired(self, client: ClientState) -> None:
        for robot in sorted(client.robots):
            self.api.stop_robot(robot)
        log.info("client %s silent for %.0f s: forgotten", client.short, client.idle_timeout)

    def describe(self) -> list[str]:
        """Human-readable lines: which robots are served under which names."""
        objs = self.api.objects
        lines = []
        for i, base in enumerate(objs.bases):
            lines.append(
                f"robot {objs.labels[i]!r}: {base.name}  (alias path /{objs.model}[{i}]; "
                f"joints {objs.joints[i][0].name}, {objs.joints[i][1].name})"
            )
        return lines


def serve_scene(
    scene: Scene | str, *, host: str = "127.0.0.1", port: int = DEFAULT_PORT, seed: int = 0,
    **options: Any,
) -> RemoteApiServer:  # fmt: skip
    """Load ``scene`` (a Scene, shipped name or file) and serve it in a background thread."""
    if isinstance(scene, str):
        from ....scenario.scenefile import load_scene

        scene = load_scene(scene)
    return RemoteApiServer(scene, host=host, port=port, seed=seed, **options).start()
