"""Your own link's timing: measured round trips, and the ``[link]`` table of a profile file.

No published figure bounds an e-puck's Bluetooth round trip, and a Wi-Fi network's
depends on the room, so ``puckboard calibrate link`` measures the one a robot is driven
over. It runs the control loop's two exchanges as fast as the link allows, with the
wheels at zero: read every sensor (one round trip, timed by the link itself:
:attr:`~puckboard.backends.epuck.link.LinkBase.round_trips`), then send a wheel command.

* the **latency** written is the median sensing round trip: the host shares no clock
  with the robot, so the sensing's age and the command's way to the wheels cannot be
  timed apart; with both ways alike, they add up to about one round trip;
* the **period** written is the 95th percentile of a whole cycle (both exchanges): the
  shortest control period the link keeps up with nineteen ticks in twenty.

Both spreads (median, 5th and 95th percentile, the largest) go into the file too, for
its reader. ``--profile FILE.toml`` then runs the simulator at that timing, rounded to
whole simulation steps (:func:`puckboard.scenario.robot_profiles.link_control`).
"""

from __future__ import annotations

import datetime
import re
import sys
import time
from collections.abc import Callable, MutableSequence, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

import numpy as np

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on 3.10 only
    import tomli as tomllib

__all__ = [
    "LinkInterrupted",
    "LinkMeasurement",
    "Spread",
    "check_link_target",
    "link_table_text",
    "measure_link",
    "write_link_table",
]

#: A link table in a profile file: its header up to the next table or the end.
_LINK_TABLE = re.compile(r"(?ms)^\[link\][^\n]*\n.*?(?=^\[|\Z)")


@dataclass(frozen=True)
class Spread:
    """How a measured time (s) spread: count, median, 5th and 95th percentile, largest."""

    n: int
    median: float
    p5: float
    p95: float
    max: float

    @classmethod
    def of(cls, seconds: Sequence[float]) -> Spread:
        if not seconds:
            raise ValueError("no times were measured")
        a = np.asarray(seconds, dtype=float)
        p5, median, p95 = np.percentile(a, [5, 50, 95])
        return cls(len(a), float(median), float(p5), float(p95), float(a.max()))

    def to_dict(self) -> dict[str, float]:
        """Seconds rounded to the microsecond, the clock's useful resolution."""
        return {
            "n": self.n,
            "median": round(self.median, 6),
            "p5": round(self.p5, 6),
            "p95": round(self.p95, 6),
            "max": round(self.max, 6),
        }


@dataclass(frozen=True)
class LinkMeasurement:
    """What a measurement found: the sensing round trips and the whole cycles (s)."""

    round_trip: Spread
    cycle: Spread

    @property
    def latency(self) -> float:
        """The loop's latency to run at (s): the median sensing round trip."""
        return self.round_trip.median

    @property
    def period(self) -> float:
        """The control period to run at (s): the 95th percentile of a whole cycle."""
        return self.cycle.p95


class _TimedLink(Protocol):
    """A link that keeps its round trips (s), as the e-puck links do."""

    @property
    def round_trips(self) -> MutableSequence[float]: ...


class _TimedAdapter(Protocol):
    """What :func:`measure_link` needs of an adapter: its link and the two calls it
    times. (The e-puck's ``Link`` protocol leaves its round trips out, so the consumer
    names them here.)"""

    @property
    def link(self) -> _TimedLink: ...

    def sense_all(self) -> object: ...

    def stop_wheels(self) -> None: ...


class LinkInterrupted(KeyboardInterrupt):
    """Ctrl-C during a measurement, carrying the ``cycles`` timed until then and what they
    measured (``measured``; ``None`` when fewer than two, too few for a spread): the
    minutes a long measurement took are kept, as ``calibrate ir`` keeps its stops."""

    def __init__(self, measured: LinkMeasurement | None, cycles: int) -> None:
        super().__init__("interrupted")
        self.measured = measured
        self.cycles = cycles


def measure_link(
    adapter: _TimedAdapter,
    rounds: int,
    *,
    clock: Callable[[], float] = time.perf_counter,
    progress: Callable[[int, int], None] | None = None,
) -> LinkMeasurement:
    """Time ``rounds`` control cycles of ``adapter`` (an
    :class:`~puckboard.backends.epuck.EPuckReal`): each reads every sensor and commands
    the wheels to zero, so the robot stays where it is. ``clock`` times the cycles; the
    link times its own round trips with its ``clock``. The wheels are zero at the end,
    whatever happens; Ctrl-C raises :class:`LinkInterrupted` with the cycles timed."""
    if rounds < 2:
        raise ValueError(f"rounds must be at least 2 to give a spread, got {rounds}")
    link = adapter.link
    link.round_trips.clear()
    cycles: list[float] = []
    try:
        for k in range(rounds):
            start = clock()
            adapter.sense_all()
            adapter.stop_wheels()
            cycles.append(clock() - start)
            if progress is not None:
                progress(k + 1, rounds)
    except KeyboardInterrupt as exc:
        kept = None
        if len(cycles) >= 2:
            kept = LinkMeasurement(Spread.of(list(link.round_trips)), Spread.of(cycles))
        raise LinkInterrupted(kept, len(cycles)) from exc
    finally:
        adapter.stop_wheels()
    return LinkMeasurement(Spread.of(list(link.round_trips)[-rounds:]), Spread.of(cycles))


def link_table_text(measured: LinkMeasurement, source: str) -> str:
    """The ``[link]`` table of a profile file (TOML), with what each number means."""
    rt, cy = measured.round_trip.to_dict(), measured.cycle.to_dict()

    def inline(d: dict[str, float]) -> str:
        return "{ " + ", ".join(f"{k} = {v!r}" for k, v in d.items()) + " }"

    escaped = source.replace("\\", "\\\\").replace('"', '\\"')
    return (
        "[link]\n"
        f"period = {round(measured.period, 6)!r}"
        "        # s: the 95th percentile of a whole cycle (sense, then command)\n"
        f"latency = {round(measured.latency, 6)!r}"
        "       # s: the median sensing round trip\n"
        f'source = "{escaped}"\n'
        f"round_trip = {inline(rt)}\n"
        f"cycle = {inline(cy)}\n"
    )


def check_link_target(path: Path) -> None:
    """Refuse, before anything is measured, a file ``path`` the ``[link]`` table cannot
    go into: one that is no TOML, or no profile file; a one-line
    :class:`~puckboard.errors.ProfileError`. A file that is not there yet is fine."""
    from ..errors import ProfileError
    from ..profile import profile_from_data

    if not path.exists():
        return
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ProfileError(f"{path}: not a TOML file ({exc})") from None
    except OSError as exc:
        raise ProfileError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    profile_from_data(data, source=str(path), default_name=path.stem)


def write_link_table(
    path: Path, measured: LinkMeasurement, source: str, *, base: str, name: str
) -> str:
    """Write the ``[link]`` table into the profile file at ``path``: replace the one it
    has, else append it (its ``[set]`` and comments stay as they are); a new file gets
    ``base`` and ``name``. Returns the text written. The result is checked by loading
    it before the file is touched."""
    from ..profile import profile_from_data

    table = link_table_text(measured, source)
    if path.exists():
        old = path.read_text(encoding="utf-8")
        text = (
            _LINK_TABLE.sub(lambda _: table + "\n", old, count=1)
            if _LINK_TABLE.search(old)
            else old.rstrip("\n") + "\n\n" + table
        )
    else:
        today = datetime.date.today().isoformat()
        text = (
            f"# {name}: its link measured with puckboard calibrate link on {today}.\n"
            f"# Use it: puckboard run two-robot-pass --profile {path.name}\n"
            f'base = "{base}"\nname = "{name}"\n\n' + table
        )
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:  # the file's own text, not the table
        from ..errors import ProfileError

        raise ProfileError(f"{path}: not a TOML file ({exc})") from None
    profile_from_data(data, source=str(path), default_name=path.stem)
    path.write_text(text, encoding="utf-8")
    return text
