"""The live view: watch a run in a matplotlib window or a Jupyter notebook.

The view is an episode observer. It reads the states a
:class:`~puckboard.recording.recorder.Recorder` has taken from the blackboard and draws
them on a :class:`~puckboard.viz.stage.Stage`, the same picture the animations use. It
never touches the simulation: pausing blocks the control loop between two cycles and
single-stepping lets exactly one cycle through, so a seeded run takes the same course with
or without a window.

Keys (window): ``space`` pause/resume, ``right`` or ``n`` one cycle while paused,
``+``/``-`` double/halve the playback speed, closing the window ends the viewing (the run
goes on without it). In a notebook with the ``widget`` (ipympl) backend the keys work too;
with the default ``inline`` backend the figure is redrawn in place a few times a second.
"""

from __future__ import annotations

import logging
import sys
import time as _time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..control.episode import Episode
    from ..recording.recorder import Recording

__all__ = ["LiveView", "Recorded"]

log = logging.getLogger(__name__)

_NON_INTERACTIVE = {"agg", "pdf", "ps", "svg", "pgf", "cairo", "template"}
_NOTEBOOK_WIDGETS = ("ipympl", "widget", "nbagg")


def can_show() -> bool:
    """Whether matplotlib can show a live figure here (a window or a notebook)."""
    import matplotlib

    return matplotlib.get_backend().lower() not in _NON_INTERACTIVE


def matplotlib_backend() -> str:
    import matplotlib

    return matplotlib.get_backend().lower()


class Recorded(Protocol):
    """What the view reads of the states taken so far: a
    :class:`~puckboard.recording.recorder.Recorder` while a run goes on, or a finished
    recording played back (:func:`replay`)."""

    #: the judge's events so far (``None``: none are known)
    events: Callable[[], list[dict[str, Any]]] | None

    @property
    def layer_names(self) -> tuple[str, ...]: ...

    def __len__(self) -> int: ...

    def arrays(self) -> dict[str, np.ndarray]: ...

    def recording(self) -> Recording: ...


class LiveView:
    """Draw a run as it happens; see the module docstring.

    ``speed`` is the playback speed relative to simulation time (1 = real time; ``None``
    = as fast as the simulation goes). ``fps`` caps the redraws per wall-clock second;
    when drawing falls behind, states are skipped, never the simulation slowed down
    further. ``figure`` is a matplotlib figure to draw on (default: a new pyplot one).
    """

    def __init__(
        self,
        recorder: Recorded,
        *,
        speed: float | None = 1.0,
        fps: float = 20.0,
        figure: Figure | None = None,
        block_at_end: bool = True,
    ) -> None:
        self.recorder = recorder
        self.speed = speed
        self.fps = fps
        self.block_at_end = block_at_end
        backend = matplotlib_backend()
        self.notebook = "inline" in backend
        self.interactive = not self.notebook and backend not in _NON_INTERACTIVE
        if figure is None and self.notebook:
            from matplotlib.backends.backend_agg import FigureCanvasAgg
            from matplotlib.figure import Figure

            figure = Figure(figsize=(12.8, 7.2), dpi=80)
            FigureCanvasAgg(figure)
        elif figure is None:
            import matplotlib.pyplot as plt

            figure = plt.figure(figsize=(12.8, 7.2))
        self.fig = figure
        rec = recorder.recording()
        from .animation import stage_for_recording

        self.stage = stage_for_recording(figure, rec)
        self._title = rec.title
        self.paused = False
        self._steps_allowed = 0
        self._closed_window = False
        self._wall0: float | None = None
        self._sim0 = 0.0
        self._last_draw = -1e9
        self.frames_drawn = 0
        self._draw_cost = 0.0  # s, smoothed cost of one redraw
        self._handle: Any = None
        if self.interactive:
            manager = getattr(figure.canvas, "manager", None)
            if manager is not None:
                manager.set_window_title(f"puckboard: {rec.title}")
            figure.canvas.mpl_connect("key_press_event", self._on_key)
            figure.canvas.mpl_connect("close_event", self._on_close_window)
            figure.canvas.mpl_connect("draw_event", self._on_draw_event)
            import matplotlib.pyplot as plt

            plt.show(block=False)
        self._set_hint()

    # -- observer --------------------------------------------------------------------------
    def attach(self, episode: Episode) -> LiveView:
        """Register as ``episode``'s cycle and close observer (after the recorder)."""
        episode.add_observer(self)
        episode.add_close_observer(self.close)
        return self

    def __call__(self, _episode: Episode | None = None) -> None:
        if self._closed_window or len(self.recorder) == 0:
            return
        arrays = self.recorder.arrays()
        t = float(arrays["time"][-1])
        now = _time.perf_counter()
        if self._wall0 is None:
            self._wall0, self._sim0 = now, t
        # At most fps redraws a second; when the run is behind its playback speed (or
        # runs flat out), at most half the time goes to drawing: states are skipped
        # rather than the run slowed down.
        behind = self.speed is None or (now - self._wall0) > (t - self._sim0) / self.speed
        interval = max(1.0 / self.fps, 2.0 * self._draw_cost) if behind else 1.0 / self.fps
        due = now - self._last_draw >= interval
        if due or self.paused:
            self._draw(arrays)
        if self.paused:
            self._wait_while_paused(arrays)
        elif self.speed is not None and self.interactive:
            ahead = (t - self._sim0) / self.speed - (_time.perf_counter() - self._wall0)
            if ahead > 0:
                self._sleep(ahead)

    def _draw(self, arrays: dict[str, np.ndarray]) -> None:
        started = _time.perf_counter()
        n = len(arrays["time"])
        names = self.recorder.layer_names
        layers = [names[k] if k >= 0 else None for k in arrays["layer"][n - 1]]
        trails = [arrays["pose"][:, r, :2] for r in range(arrays["pose"].shape[1])]
        self.stage.update(
            float(arrays["time"][-1]),
            arrays["pose"][-1],
            arrays["proximity"][-1],
            arrays["ground"][-1],
            layers,
            trails,
            self._events(),
        )
        self.frames_drawn += 1
        self._last_draw = started
        if self.notebook:
            self._show_inline()
        else:
            self.stage.render()
            if self.interactive:
                canvas = self.fig.canvas
                canvas.blit(self.fig.bbox)
                canvas.flush_events()
        cost = _time.perf_counter() - started
        self._draw_cost = cost if self.frames_drawn == 1 else 0.8 * self._draw_cost + 0.2 * cost

    def _events(self) -> list[dict[str, Any]]:
        source = self.recorder.events
        if source is None:
            return []
        try:
            return list(source())
        except Exception:  # a view must never break a run
            return []

    def _show_inline(self) -> None:
        """Inline notebooks show pictures, not canvases: render off-screen and update
        one displayed image in place."""
        from IPython.display import display
        from PIL import Image

        image = Image.fromarray(self.stage.frame_rgb())
        if self._handle is None:
            self._handle = display(image, display_id=True)
        else:
            self._handle.update(image)

    def _sleep(self, seconds: float) -> None:
        if self.interactive:
            self.fig.canvas.start_event_loop(max(seconds, 1e-3))
        else:
            _time.sleep(seconds)

    def _wait_while_paused(self, arrays: dict[str, np.ndarray]) -> None:
        while self.paused and not self._closed_window:
            if self._steps_allowed > 0:
                self._steps_allowed -= 1
                break
            self._sleep(0.05)
        # re-anchor pacing so a long pause does not make the run race to catch up
        self._wall0 = _time.perf_counter()
        self._sim0 = float(arrays["time"][-1])

    # -- keys ------------------------------------------------------------------------------
    def _on_key(self, event: Any) -> None:
        key = event.key
        if key == " ":
            self.paused = not self.paused
        elif key in ("right", "n"):
            self.paused = True
            self._steps_allowed += 1
        elif key in ("+", "="):
            self.speed = (self.speed or 1.0) * 2.0
        elif key in ("-", "_"):
            self.speed = max(0.125, (self.speed or 1.0) / 2.0)
        else:
            return
        self._set_hint()
        self._draw_now()

    def _set_hint(self) -> None:
        speed = "max" if self.speed is None else f"{self.speed:g}×"
        state = "PAUSED, right/n: step" if self.paused else "space: pause"
        self.stage.set_footer(f"{state}   +/-: speed ({speed})" if self.interactive else "")

    def _draw_now(self) -> None:
        if len(self.recorder) > 0 and not self._closed_window:
            self._draw(self.recorder.arrays())

    def _on_draw_event(self, event: Any) -> None:
        self.stage.on_draw_event(event)
        self.fig.canvas.blit(self.fig.bbox)

    def _on_close_window(self, _event: Any) -> None:
        self._closed_window = True
        log.info("live view closed; the run goes on without it")

    # -- end -------------------------------------------------------------------------------
    def close(self, _episode: Episode | None = None) -> None:
        """Draw the final state; in a window, keep it open until the user closes it
        (unless the run ended with an error or Ctrl-C)."""
        if self._closed_window or len(self.recorder) == 0:
            return
        failing = sys.exc_info()[0] is not None
        try:
            self._draw(self.recorder.arrays())
        except Exception as exc:
            if not failing:
                raise
            # Ctrl-C can tear the window down under us (Tk raises TclError): the run's
            # own exception is the one to report, not a failed last redraw
            log.debug("final redraw skipped while stopping: %s", exc)
            return
        if not self.interactive:
            return
        in_widget = any(w in matplotlib_backend() for w in _NOTEBOOK_WIDGETS)
        if self.block_at_end and not failing and not in_widget:
            self.stage.set_footer("finished: close the window to exit")
            self._draw_now()
            import matplotlib.pyplot as plt

            plt.show(block=True)


class _Replay:
    """A finished recording played back row by row, looking like a recorder to the view."""

    def __init__(self, rec: Recording) -> None:
        self.rec = rec
        self.n = 0
        self.layer_names = rec.layer_names
        self.events: Callable[[], list[dict[str, Any]]] | None = lambda: list(
            rec.meta.get("events") or []
        )

    def __len__(self) -> int:
        return self.n

    def recording(self) -> Recording:
        return self.rec

    def arrays(self) -> dict[str, np.ndarray]:
        """The recording's arrays (its own mapping) up to the row being shown."""
        return {name: values[: self.n] for name, values in self.rec.arrays().items()}


def replay(
    rec: Recording, *, speed: float | None = 1.0, figure: Figure | None = None
) -> LiveView:
    """Play a recording back in the live view (same keys: pause, step, speed)."""
    source = _Replay(rec)
    view = LiveView(source, speed=speed, figure=figure)
    for i in range(len(rec)):
        source.n = i + 1
        view()
        if view._closed_window:
            break
    view.close()
    return view
