"""Wiring the visual tools to a run: what ``puckboard run --view/--record/--plots/--monitor`` do.

:func:`attach` registers observers on an episode before it runs. Everything that needs
the run's states shares one :class:`~puckboard.recording.recorder.Recorder`, registered first so
the live view and the end-of-run outputs read the states of the cycle just finished.
Outputs that need extra packages are checked here, before the run starts, so a missing
MP4 writer is reported in a second and not after a two-minute run.

When the run ends (normally, on an error or on Ctrl-C) one close observer writes the
outputs in order of value: the data recording first (cheap, and everything else can be
made from it later), then the animation, then the plots. A Ctrl-C while they are written
after a complete run only says what a second one would lose; the second abandons the
animation. Either way the command then ends as interrupted.
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
import threading
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..recording.recorder import Recorder

if TYPE_CHECKING:
    from types import FrameType

    from ..control.episode import Episode

__all__ = ["RunOutputs", "attach"]

log = logging.getLogger(__name__)


class RunOutputs:
    """The tools attached to one episode, and the files they wrote (``written``)."""

    def __init__(self) -> None:
        self.recorder: Recorder | None = None
        self.view: Any = None
        self.monitor: Any = None
        self.animation: Path | None = None
        self.plots_dir: Path | None = None
        self.plot_format = "png"
        self.written: list[Path] = []

    def finish(self, episode: Episode | None = None) -> None:
        """Write the outputs; each failure is logged and does not stop the others."""
        if self.recorder is None:
            return
        interrupted = bool(getattr(getattr(episode, "loop", None), "interrupted", False))
        rec = self.recorder.close()
        if self.recorder.saved_path is not None:
            self.written.append(self.recorder.saved_path)
            if interrupted:
                log.warning(
                    "interrupted: the recording so far (%d cycles) is kept in %s",
                    len(rec),
                    self.recorder.saved_path,
                )
        if len(rec) == 0:
            log.warning("the run ended before its first cycle: no animation or plots written")
            return
        asked_to_stop = _FirstCtrlC(
            f"Ctrl-C: the run is over and its animation {self.animation} is being written; "
            "press Ctrl-C again to abandon it"
        )
        if self.animation is not None:
            from .animation import render_animation

            if interrupted:
                log.warning(
                    "interrupted: writing the animation %s from the %d cycles recorded; "
                    "press Ctrl-C again to abandon it",
                    self.animation,
                    len(rec),
                )
            try:
                # after a complete run one Ctrl-C must not throw the animation away: it
                # only warns, and the next one abandons it (as during the run)
                with asked_to_stop if not interrupted else contextlib.nullcontext():
                    self.written.append(render_animation(rec, self.animation)["path"])
            except KeyboardInterrupt:
                log.warning("the animation %s was abandoned", self.animation)
                self.animation.unlink(missing_ok=True)  # never leave half a file behind
                raise
            except Exception:
                log.exception("could not write the animation %s", self.animation)
        if self.plots_dir is not None:
            from .plots import save_plots

            try:
                self.written += save_plots(rec, self.plots_dir, self.plot_format)
            except Exception:
                log.exception("could not write the plots to %s", self.plots_dir)
        if asked_to_stop.pressed:
            log.warning("the animation %s is written; stopping as Ctrl-C asked", self.animation)
            raise KeyboardInterrupt  # the command ends as interrupted (status 130)


class _FirstCtrlC:
    """While active, the first Ctrl-C only logs ``message`` (and sets :attr:`pressed`);
    the second raises ``KeyboardInterrupt`` as usual.

    Only the main thread may set a signal handler; elsewhere (a run driven from another
    thread) Ctrl-C keeps its usual effect.
    """

    def __init__(self, message: str) -> None:
        self.message = message
        self.pressed = False
        self._installed = False
        self._previous: Any = None

    def _on_sigint(self, signum: int, frame: FrameType | None) -> None:
        if self.pressed:
            raise KeyboardInterrupt
        self.pressed = True
        log.warning("%s", self.message)

    def __enter__(self) -> _FirstCtrlC:
        previous = signal.getsignal(signal.SIGINT)
        # a handler set outside Python (None) cannot be put back: leave Ctrl-C alone then
        if threading.current_thread() is threading.main_thread() and previous is not None:
            self._previous = signal.signal(signal.SIGINT, self._on_sigint)
            self._installed = True
        return self

    def __exit__(self, *exc: object) -> None:
        if self._installed:
            signal.signal(signal.SIGINT, self._previous)
            self._installed = False


def attach(
    episode: Episode,
    *,
    view: bool = False,
    record: str | os.PathLike[str] | None = None,
    plots: str | os.PathLike[str] | None = None,
    monitor: bool = False,
    plot_format: str = "png",
    speed: float | None = 1.0,
) -> RunOutputs:
    """Attach the visual tools to ``episode`` before :meth:`run`.

    ``view``: a live window (or notebook figure). ``record``: ``.npz`` saves the data
    recording, ``.gif``/``.mp4`` an animation rendered from it. ``plots``: a directory
    for the post-run plots (``plot_format`` png or svg). ``monitor``: a live terminal
    table of every robot's blackboard keys. ``speed``: live-view playback speed (1 =
    real time, ``None`` = as fast as possible). Raises ``ValueError`` (bad file name) or
    :class:`~puckboard.viz.animation.VideoSupportError` (missing package) before
    anything runs.
    """
    outputs = RunOutputs()
    npz_path: Path | None = None
    if record is not None:
        path = Path(record)
        suffix = path.suffix.lower()
        if suffix == ".npz":
            npz_path = path
        else:
            from .animation import check_animation_path

            try:
                outputs.animation = check_animation_path(path)
            except ValueError:
                raise ValueError(
                    f"--record {str(path)!r}: use a .npz (data), .gif or .mp4 file name"
                ) from None
    if plots is not None:
        from .plots import PLOT_FORMATS

        if plot_format not in PLOT_FORMATS:
            raise ValueError(f"plot format must be one of {', '.join(PLOT_FORMATS)}")
        p = Path(plots)
        if p.exists() and not p.is_dir():
            raise ValueError(f"--plots {str(p)!r} is a file; give a directory for the plots")
        outputs.plots_dir = p
        outputs.plot_format = plot_format
    if view or record is not None or plots is not None:
        outputs.recorder = Recorder.for_episode(episode, npz_path)
        episode.add_observer(outputs.recorder)
        episode.add_close_observer(outputs.finish)
    if view:
        from .live import LiveView, can_show

        assert outputs.recorder is not None
        if can_show():
            # A real robot's loop keeps wall-clock time and every redraw is taken out
            # of a control period: redraw less often there.
            realtime = not getattr(getattr(episode, "loop", None), "synchronous", True)
            outputs.view = LiveView(
                outputs.recorder, speed=speed, fps=5.0 if realtime else 20.0
            ).attach(episode)
        else:
            log.warning(
                "--view needs a display, and matplotlib found none (backend %s); running "
                "without the view. Record the run instead: --record run.gif",
                _backend(),
            )
    if monitor:
        from .monitor import SensorMonitor

        outputs.monitor = SensorMonitor.for_episode(episode).attach(episode)
    return outputs


def _backend() -> str:
    import matplotlib

    return str(matplotlib.get_backend())
