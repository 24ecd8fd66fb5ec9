"""The sensor monitor: a live terminal table of every robot's blackboard keys.

For each key it shows the newest value (formatted with names and units), its age and
how often it is updated, and marks stale or missing values in red. It reads only the
blackboard, so it works the same with the embedded simulator, CoppeliaSim and a real
e-puck; a sensor that stops arriving shows up at once as a growing age and a falling
rate instead of a frozen number.

Age and rate are measured on the blackboard's clock: simulated seconds in a simulator,
wall-clock seconds on a real robot. In a terminal the table redraws in place (rich's
``Live``); when the output is a file or a pipe, a plain table is printed every
``plain_every`` wall-clock seconds and once at the end, with no escape codes.
"""

from __future__ import annotations

import math
import time as _time
from collections import deque
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ..blackboard import Blackboard
    from ..control.episode import Episode

__all__ = ["SensorMonitor", "format_value"]

_WINDOW = 2.0  # s of blackboard time over which update rates are measured


def format_value(value: Any) -> str:
    """A short, human-readable rendering of a blackboard value, with units."""
    from ..records import (
        PROX_NAMES,
        Acceleration,
        AngularVelocity,
        CameraImage,
        Ground,
        Light,
        Pose,
        Proximity,
        WheelCommand,
        WheelEncoders,
        WheelSpeeds,
    )

    if isinstance(value, Proximity):
        seen = [
            f"{name} {100 * d:.1f}"
            for name, d in zip(PROX_NAMES, value.distance)
            if d < value.range
        ]
        if not seen:
            return f"nothing within {100 * value.range:g} cm"
        return ", ".join(seen) + " cm"
    if isinstance(value, Ground):
        return "L {:.2f}  C {:.2f}  R {:.2f}".format(*value.value)
    if isinstance(value, Pose):
        gt = " (truth)" if value.ground_truth else ""
        return f"x {value.x:+.3f} m  y {value.y:+.3f} m  θ {math.degrees(value.theta):+6.1f}°{gt}"
    if isinstance(value, (WheelCommand, WheelSpeeds)):
        return f"L {value.left:+.2f}  R {value.right:+.2f} rad/s"
    if isinstance(value, WheelEncoders):
        return f"L {value.left:+.1f}  R {value.right:+.1f} rad"
    if isinstance(value, Acceleration):
        return f"x {value.x:+.2f}  y {value.y:+.2f}  z {value.z:+.2f} m/s²"
    if isinstance(value, AngularVelocity):
        return f"x {value.x:+.2f}  y {value.y:+.2f}  z {value.z:+.2f} rad/s"
    if isinstance(value, Light):
        return "raw " + " ".join(f"{v:.0f}" for v in value.raw)
    if isinstance(value, CameraImage):
        return f"{value.width}×{value.height} image"
    if isinstance(value, float):
        return f"{value:.4g}"
    text = str(value)
    return text if len(text) <= 60 else text[:57] + "..."


class SensorMonitor:
    """Watches ``robots``' keys on ``board``; call it after each cycle, :meth:`close` at
    the end. ``console`` is a rich console (default: one on stdout)."""

    def __init__(
        self,
        board: Blackboard,
        robots: Sequence[str],
        *,
        console: Any = None,
        refresh: float = 4.0,
        plain_every: float = 10.0,
        title: str = "",
    ) -> None:
        from rich.console import Console

        self.board = board
        self.robots = tuple(robots)
        self.console = console if console is not None else Console()
        self.refresh = refresh
        self.plain_every = plain_every
        self.title = title
        self._history: dict[str, deque[tuple[float, int]]] = {}
        self._live: Any = None
        self._last_render = -1e9
        self._closed = False

    @classmethod
    def for_episode(cls, episode: Episode, **options: Any) -> SensorMonitor:
        robots = list(getattr(episode, "controllers", {}) or episode.connection.adapters)
        scene = getattr(episode, "scene", None)
        title = " · ".join(
            str(x)
            for x in (
                getattr(scene, "name", None),
                getattr(episode, "backend", None),
                f"seed {episode.seed}" if getattr(episode, "seed", None) is not None else None,
            )
            if x
        )
        return cls(episode.blackboard, robots, title=title, **options)

    def attach(self, episode: Episode) -> SensorMonitor:
        episode.add_observer(self)
        episode.add_close_observer(self.close)
        return self

    # -- sampling --------------------------------------------------------------------------
    def sample(self) -> None:
        """Note the newest sequence number of every key (for the update rates)."""
        now = self.board.clock()
        for robot in self.robots:
            snap = self.board.snapshot(prefix=robot + "/")
            for key in snap:
                rec = snap.record(key)
                if rec is None:
                    continue
                hist = self._history.setdefault(key, deque())
                if not hist or hist[-1][1] != rec.seq:
                    hist.append((rec.stamp, rec.seq))
                while len(hist) > 2 and now - hist[0][0] > _WINDOW:
                    hist.popleft()

    def rate(self, key: str, *, stale: bool = False) -> float | None:
        """Updates per second of ``key`` over the last couple of seconds (``None``: unknown).

        For a ``stale`` key the span runs to now, so a sensor that stopped arriving
        shows a rate falling towards zero rather than its last good value."""
        hist = self._history.get(key)
        if not hist or len(hist) < 2:
            return None
        (t0, s0), (t1, s1) = hist[0], hist[-1]
        end = max(t1, self.board.clock()) if stale else t1
        return (s1 - s0) / (end - t0) if end > t0 else None

    def __call__(self, _episode: Episode | None = None) -> None:
        if self._closed:
            return
        self.sample()
        wall = _time.monotonic()
        if self.console.is_terminal:
            if wall - self._last_render >= 1.0 / self.refresh:
                self._last_render = wall
                if self._live is None:
                    from rich.live import Live

                    self._live = Live(
                        self.table(), console=self.console, auto_refresh=False, transient=False
                    )
                    self._live.start()
                self._live.update(self.table(), refresh=True)
        elif wall - self._last_render >= self.plain_every:
            # into a pipe or a file: the first table at once, so a reader ('| tee log')
            # sees the run has started, then one every plain_every seconds, each flushed
            self.console.print(self.table())
            self._flush()
            self._last_render = wall

    def close(self, _episode: Episode | None = None) -> None:
        """Show the final table (and leave it on screen)."""
        if self._closed:
            return
        self._closed = True
        self.sample()
        if self._live is not None:
            self._live.update(self.table(), refresh=True)
            self._live.stop()
        else:
            self.console.print(self.table())
            self._flush()

    def _flush(self) -> None:
        flush = getattr(self.console.file, "flush", None)
        if flush is not None:
            flush()

    # -- rendering -------------------------------------------------------------------------
    def table(self) -> Any:
        """The current table as a rich renderable."""
        from rich.table import Table
        from rich.text import Text

        now = self.board.clock()
        table = Table(
            title=f"blackboard{': ' + self.title if self.title else ''}   t = {now:.2f} s",
            title_justify="left",
            expand=False,
        )
        table.add_column("robot", style="bold")
        table.add_column("key")
        table.add_column("value", overflow="fold")
        table.add_column("age (s)", justify="right")
        table.add_column("rate (Hz)", justify="right")
        for robot in self.robots:
            snap = self.board.snapshot(prefix=robot + "/")
            first = True
            for key in sorted(snap):
                rec = snap.record(key)
                status = snap.status(key)
                short = key[len(robot) + 1 :]
                if rec is None:
                    value, age, style = Text("not written (yet)", style="dim"), "", "dim"
                else:
                    style = "red" if status == "stale" else ""
                    value = Text(format_value(rec.value), style=style)
                    age = f"{now - rec.stamp:.2f}"
                rate = self.rate(key, stale=status == "stale")
                table.add_row(
                    robot if first else "",
                    Text(short, style=style),
                    value,
                    Text(age, style=style),
                    "" if rate is None else f"{rate:.1f}",
                )
                first = False
            table.add_section()
        return table

    def render_text(self, width: int = 120) -> str:
        """The current table as plain text (no colours, no escape codes)."""
        from rich.console import Console

        console = Console(width=width, record=True, force_terminal=False, color_system=None)
        with console.capture() as capture:
            console.print(self.table())
        return capture.get()
