"""A live browser view of a simulation, for the projector and every student's laptop.

``puckboard serve SCENE --web`` and ``puckboard run SCENE --web`` also serve a web page
drawing the arena live: every robot with its name, heading, trail and IR readings, the
simulation time and real-time factor, per robot the layer in control, its wheel command
and who drives it, the judge's events and verdict; click a robot for its blackboard keys
and its arbitration timeline. The page is plain HTML and JavaScript shipped in the
package (no CDN: it works offline) and read-only.

* :mod:`.state` — what the page shows, built from a run or a served world;
* :mod:`.server` — the aiohttp server: the page, a Server-Sent Events stream;
* :mod:`.replay` — a recorded run as one document the page's player scrubs through
  (``puckboard replay RUN.npz --web``);
* :mod:`.export` — that player as one self-contained HTML file (``--html``), which
  :func:`show_replay` shows inline in a Jupyter notebook.

Serving needs the ``web`` extra (``pip install "puckboard[web]"``, aiohttp); writing the
one-file player does not.
"""

from __future__ import annotations

import html
import os
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ..backends.coppeliasim.server.socket_loop import RemoteApiServer
    from ..control.episode import Episode
    from ..recording.recorder import Recording
    from .server import WebView

__all__ = ["show_replay", "watch_episode", "watch_server"]


def watch_episode(
    episode: Episode, *, host: str = "127.0.0.1", port: int = 8080, speed: float | None = 1.0
) -> WebView:
    """Serve a live view of ``episode`` (before :meth:`run`); returns the started
    :class:`~puckboard.web.server.WebView`. ``speed`` paces the run to the wall clock
    (1 = real time, ``None`` = as fast as it goes) so people can watch it; pacing only
    waits between cycles, the run's results are the same."""
    from ..control.pacing import RealTimePacer
    from .server import WebView
    from .state import EpisodeFollower

    view = WebView(host=host, port=port).start()
    follower = EpisodeFollower(episode, view.publish)
    view.follow(follower)
    episode.add_observer(follower)
    episode.add_close_observer(follower.close)
    episode.add_result_observer(follower.close)  # again, with the judge's final verdict
    if speed is not None:
        episode.add_observer(RealTimePacer(speed))
    return view


def watch_server(
    server: RemoteApiServer, *, host: str = "127.0.0.1", port: int = 8080
) -> WebView:
    """Serve a live view of a
    :class:`~puckboard.backends.coppeliasim.server.socket_loop.RemoteApiServer`'s world;
    returns the started :class:`~puckboard.web.server.WebView`."""
    from .server import WebView
    from .state import ServerFollower

    view = WebView(host=host, port=port).start()
    follower = ServerFollower(server.view(), view.publish)
    view.follow(follower)
    server.add_step_observer(follower)
    return view


def show_replay(recording: Recording | str | os.PathLike[str], *, height: int = 720) -> Any:
    """Show ``recording`` (a :class:`~puckboard.recording.recorder.Recording` or the path
    of one) in the web view's player, inline in a Jupyter notebook: the one-file export
    of ``puckboard replay --html`` in an iframe, so it needs no server. Returns an
    ``IPython.display.HTML`` object (a notebook shows it when it is a cell's last value).
    """
    from ..recording.recorder import load_recording
    from .export import replay_html

    try:
        from IPython.display import HTML
    except ImportError:
        raise ImportError(
            "puckboard.web.show_replay shows the player inside Jupyter and needs IPython "
            "(run it in a notebook); elsewhere write the player to a file: "
            "puckboard replay RUN.npz --html run.html"
        ) from None
    if isinstance(recording, (str, os.PathLike)):
        recording = load_recording(recording)
    page = html.escape(replay_html(recording), quote=True)
    return HTML(
        f'<iframe srcdoc="{page}" style="width: 100%; height: {int(height)}px; border: 0" '
        'sandbox="allow-scripts" title="puckboard replay"></iframe>'
    )
