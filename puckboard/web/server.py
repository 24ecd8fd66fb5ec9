"""The web server of the live view: one page, its two static files, and a stream.

An aiohttp application runs in a daemon thread with its own event loop, so it never
shares a thread with the simulation. The simulation side calls :meth:`WebView.publish`
(from whatever thread steps it); the message is encoded **once** and handed to the
loop, and every connected browser gets that same bytes object over Server-Sent Events
(``/stream``). Thirty browsers therefore cost thirty socket writes, not thirty
encodings, and a slow browser only delays itself: each stream sends the newest frame
and skips the ones it was too slow for.

Read-only by design: the routes are GET only (anything else is answered 405), the static
files are read from the package into memory at start (no path from a request ever
touches the file system), and nothing a browser sends reaches the simulation.
Binds 127.0.0.1 unless told otherwise.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import threading
from importlib import resources
from typing import TYPE_CHECKING, Any

from aiohttp import web

if TYPE_CHECKING:
    from .state import EpisodeFollower, ServerFollower

__all__ = ["DEFAULT_WEB_PORT", "WebView"]

log = logging.getLogger(__name__)

#: Default port of the web view.
DEFAULT_WEB_PORT = 8080
_STATIC = {"/": ("index.html", "text/html"), "/view.js": ("view.js", "text/javascript"),
           "/replay.js": ("replay.js", "text/javascript"),
           "/view.css": ("view.css", "text/css")}  # fmt: skip
#: Messages the page fetches when it needs them instead of receiving them on the stream.
_FETCHED = frozenset({"details", "replay"})
_KEEPALIVE_S = 15.0
#: The page's title as index.html has it: a served replay's page says "replay" instead.
_LIVE_TITLE = "<title>puckboard — live view</title>".encode()


class WebView:
    """A live view served at ``http://host:port/``; ``port=0`` picks a free port.

    ``publish(kind, data)`` sends ``scene``, ``frame`` or ``details`` messages; the page
    fetches the newest scene, trails and details on connect. A ``replay`` message (a
    whole recorded run, :mod:`.replay`) turns the page into a player.
    """

    def __init__(self, *, host: str = "127.0.0.1", port: int = DEFAULT_WEB_PORT) -> None:
        self.host = host
        self.requested_port = port
        self.port = port
        self.clients = 0
        #: what feeds the view (a follower of :mod:`.state`), set by :meth:`follow`
        self.follower: Any = None
        self._latest: dict[str, bytes] = {}
        self._event: asyncio.Event | None = None
        self._data = b""
        self._loop: asyncio.AbstractEventLoop | None = None
        self._runner: web.AppRunner | None = None
        self._thread: threading.Thread | None = None
        self._static = {
            path: (
                resources.files(__package__).joinpath("static").joinpath(name).read_bytes(),
                kind,
            )
            for path, (name, kind) in _STATIC.items()
        }

    # -- lifecycle ---------------------------------------------------------------------------
    @property
    def url(self) -> str:
        host = "127.0.0.1" if self.host in ("127.0.0.1", "localhost") else self.host
        return f"http://{host}:{self.port}/"

    def start(self) -> WebView:
        """Bind and serve in a daemon thread; raises ``OSError`` if the port is taken."""
        ready = threading.Event()
        failure: list[BaseException] = []

        def run() -> None:
            loop = asyncio.new_event_loop()
            self._loop = loop
            asyncio.set_event_loop(loop)
            try:
                loop.run_until_complete(self._serve())
            except BaseException as exc:  # reported to start()
                failure.append(exc)
                ready.set()
                loop.close()
                return
            ready.set()
            try:
                loop.run_forever()
            finally:
                loop.run_until_complete(self._shutdown())
                loop.close()

        self._thread = threading.Thread(target=run, name=f"web-view:{self.port}", daemon=True)
        self._thread.start()
        ready.wait(10.0)
        if failure:
            exc = failure[0]
            raise OSError(
                f"cannot serve the web view on {self.host}:{self.requested_port}: {exc}"
            ) from exc
        return self

    def close(self, timeout: float = 5.0) -> None:
        """Stop serving; the streams end. Idempotent."""
        loop = self._loop
        if loop is not None and loop.is_running():
            loop.call_soon_threadsafe(loop.stop)
        if self._thread is not None:
            self._thread.join(timeout)
        self._loop = None

    def __enter__(self) -> WebView:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    async def _serve(self) -> None:
        app = web.Application()
        app.router.add_get("/", self._static_file)
        for path in _STATIC:
            if path != "/":
                app.router.add_get(path, self._static_file)
        app.router.add_get("/scene.json", self._message("scene"))
        app.router.add_get("/frame.json", self._message("frame"))
        app.router.add_get("/details.json", self._message("details"))
        app.router.add_get("/replay.json", self._message("replay"))
        app.router.add_get("/trails.json", self._trails_json)
        app.router.add_get("/stream", self._stream)
        self._event = asyncio.Event()
        self._runner = web.AppRunner(app, access_log=None, handle_signals=False)
        await self._runner.setup()
        site = web.TCPSite(self._runner, self.host, self.requested_port)
        await site.start()
        server = site._server
        sockets = getattr(server, "sockets", None) or []
        if sockets:
            self.port = int(sockets[0].getsockname()[1])

    async def _shutdown(self) -> None:
        if self._event is not None:
            self._event.set()  # wake the streams so they end
        if self._runner is not None:
            await self._runner.cleanup()

    # -- publishing (any thread) ---------------------------------------------------------------
    def follow(self, follower: EpisodeFollower | ServerFollower) -> None:
        """Show what ``follower`` (a :mod:`.state` follower) publishes; ``/trails.json``
        answers its trails so far."""
        self.follower = follower

    def publish(self, kind: str, data: Any) -> None:
        """Send ``{"kind": kind, "data": data}`` to every page (encoded here, once)."""
        body = json.dumps(data, separators=(",", ":"), allow_nan=False).encode()
        message = b"event: " + kind.encode() + b"\ndata: " + body + b"\n\n"
        loop = self._loop
        if loop is None:
            self._latest[kind] = body
            return
        with contextlib.suppress(RuntimeError):  # the loop closed meanwhile
            loop.call_soon_threadsafe(self._deliver, kind, body, message)

    def _deliver(self, kind: str, body: bytes, message: bytes) -> None:
        self._latest[kind] = body
        if kind in _FETCHED:
            return  # fetched by the page (the panel, the player), not streamed
        self._data = message
        old, self._event = self._event, asyncio.Event()
        if old is not None:
            old.set()

    # -- handlers (web thread) -----------------------------------------------------------------
    async def _static_file(self, request: web.Request) -> web.Response:
        body, kind = self._static[request.path]
        if request.path == "/" and "replay" in self._latest:  # the tab names what it shows
            body = body.replace(_LIVE_TITLE, "<title>puckboard — replay</title>".encode())
        return web.Response(body=body, content_type=kind, headers={"Cache-Control": "no-cache"})

    def _message(self, kind: str) -> Any:
        async def handler(request: web.Request) -> web.Response:
            body = self._latest.get(kind, b"null")
            return web.Response(body=body, content_type="application/json")

        return handler

    async def _trails_json(self, request: web.Request) -> web.Response:
        trails = self.follower.trails_json() if self.follower is not None else {}
        return web.json_response(trails)

    async def _stream(self, request: web.Request) -> web.StreamResponse:
        response = web.StreamResponse(headers={
            "Content-Type": "text/event-stream", "Cache-Control": "no-cache",
            "X-Accel-Buffering": "no",
        })  # fmt: skip
        await response.prepare(request)
        self.clients += 1
        try:
            if self._data:
                await response.write(self._data)
            while True:
                event = self._event
                assert event is not None
                try:
                    await asyncio.wait_for(event.wait(), _KEEPALIVE_S)
                except asyncio.TimeoutError:
                    await response.write(b": keep-alive\n\n")
                    continue
                if self._loop is None or not self._data:
                    break
                await response.write(self._data)
        except (ConnectionResetError, asyncio.CancelledError):
            pass
        finally:
            self.clients -= 1
        return response
