"""A challenge file: what students practise on, what they are graded on, how they rank.

A challenge is a TOML file (``docs/challenges.md`` documents every field; the shipped
ones are in ``puckboard/challenge/shipped/``, ``puckboard challenge list`` names them).
It holds two sets of *cells*, each cell a scene with the robots, conditions and link
timing its episodes run under:

* the **practice** set, on public seeds: what ``puckboard challenge check`` runs, and
  what students may run as often as they like;
* the **graded** set, any mix of shipped scenes, scene files, ``generated-pass``,
  ``variation = "plausible"`` or ``"reality-gap"``, profiles and link timings, whose
  seeds come from the lecturer's secret (:mod:`puckboard.challenge.seeds`).

It also says how many episodes each graded cell runs, the wall-clock limits of an
episode and of the pre-flight check, the memory a submission may take, the baselines
every submission is shown against and the ranking rule.

Everything is checked when the file is read: an unknown key, a scene or profile that
does not exist, a parameter a sweep would refuse. Each mistake is one
:class:`~puckboard.errors.ChallengeError` line naming the file, the table and the fix.
"""

from __future__ import annotations

import hashlib
import json
import re
import sys
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import ChallengeError, PuckboardError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

if TYPE_CHECKING:
    from ..scenario.reader import TableReader
    from ..scenario.scene import Scene

__all__ = [
    "RANKING_KEYS",
    "Cell",
    "Challenge",
    "challenge_names",
    "identity_differences",
    "load_challenge",
    "parse_challenge",
]

#: What the ranking can order by, each with its direction and its words on the page.
RANKING_KEYS: dict[str, str] = {
    "worst_cell_success": "the success rate of its worst graded cell (higher first)",
    "success": "its success rate over every graded episode (higher first)",
    "success_low": "the lower end of that rate's 95 % interval (higher first)",
    "median_progress": "its median progress over the graded episodes, in laps (higher first)",
    "collisions": "its mean collisions per episode (fewer first)",
}
DEFAULT_RANKING = ("worst_cell_success", "success", "median_progress")

_TOP = ("name", "title", "description", "factory", "limits", "ranking", "practice", "graded")
_LIMITS = ("episode_timeout", "check_timeout", "memory_mib")
_RANKING = ("order", "baselines")
_PRACTICE = ("seeds", "cells")
_GRADED = ("episodes", "cells")
_CELL = ("name", "scene", "profile", "variation", "link", "duration", "set")
_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,39}$")
#: The pre-flight check's limit when the file gives none (s): importing a file, building
#: its controller and timing its first ticks take a second or two.
CHECK_TIMEOUT = 30.0
#: Memory a submission's process may take beyond what it holds at start (MiB).
MEMORY_MIB = 1024
#: Most episodes a graded cell may run, and seeds a practice set may name.
MAX_EPISODES = 1000


@dataclass(frozen=True)
class Cell:
    """One scene with its robots, conditions and link timing, run on several seeds."""

    name: str
    scene: Scene
    #: the cell's fixed episode parameters (sweep ``--set`` names), ``label.cell`` included
    parameters: Mapping[str, Any]
    #: what the file said, for describing the cell: scene, profile, variation, link ...
    written: Mapping[str, Any] = field(default_factory=dict)

    def describe(self) -> str:
        """``scene · profile · variation · link · settings``, as the file gave them."""
        parts = [str(self.written.get("scene", self.scene.name))]
        for key in ("profile", "variation", "link"):
            if self.written.get(key) not in (None, "none"):
                parts.append(f"{key} {self.written[key]}")
        if self.written.get("duration") is not None:
            parts.append(f"{self.written['duration']:g} s")
        parts += [f"{k}={v}" for k, v in sorted(dict(self.written.get("set") or {}).items())]
        return " · ".join(parts)


@dataclass(frozen=True)
class Challenge:
    """A challenge file, read and checked; see the module docstring."""

    name: str
    title: str
    description: str
    source: str
    factory: str
    practice: tuple[Cell, ...]
    practice_seeds: range
    graded: tuple[Cell, ...]
    episodes: int
    episode_timeout: float
    check_timeout: float
    memory_mib: int | None
    ranking: tuple[str, ...]
    baselines: tuple[str, ...]

    def cell(self, name: str) -> Cell:
        for cell in (*self.graded, *self.practice):
            if cell.name == name:
                return cell
        raise KeyError(name)

    def identity(self) -> dict[str, Any]:
        """What graded results depend on: the name, the controller factory, the graded
        cells (their scenes' content included), the episodes and the episode limit. Two
        challenges of equal identity give the same episodes; the ranking rule, the
        baselines and the practice set may change without a run being redone."""
        return {
            "name": self.name,
            "factory": self.factory,
            "episodes": self.episodes,
            "episode_timeout": self.episode_timeout,
            "cells": {
                c.name: {"parameters": _plain(c.parameters), "scene": _scene_digest(c.scene)}
                for c in self.graded
            },
        }

    def differences(self, stored: Mapping[str, Any]) -> list[str]:
        """How :meth:`identity` differs from ``stored`` (another run's), in words."""
        return identity_differences(self.identity(), stored)


def identity_differences(mine: Mapping[str, Any], stored: Mapping[str, Any]) -> list[str]:
    """How one :meth:`Challenge.identity` differs from another (``stored``), in words."""
    said = []
    for key in ("name", "factory", "episodes", "episode_timeout"):
        if stored.get(key) != mine.get(key):
            said.append(f"{key} {stored.get(key)!r} there, {mine.get(key)!r} here")
    theirs = dict(stored.get("cells") or {})
    cells = dict(mine.get("cells") or {})
    for name in sorted(set(theirs) | set(cells)):
        if name not in cells:
            said.append(f"graded cell {name!r} is there, not here")
        elif name not in theirs:
            said.append(f"graded cell {name!r} is here, not there")
        elif theirs[name] != cells[name]:
            said.append(f"graded cell {name!r} differs")
    return said


def _plain(value: Any) -> Any:
    return json.loads(json.dumps(value, sort_keys=True, default=str))


def _scene_digest(scene: Scene) -> str:
    """A digest of a scene's content: a cell whose scene file changed is another cell."""
    from ..scenario.conversion import scene_to_dict

    text = json.dumps(_plain(scene_to_dict(scene)), sort_keys=True)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


# -- reading -------------------------------------------------------------------------------
def challenge_names() -> list[str]:
    """The shipped challenges, by name."""
    folder = resources.files(__package__).joinpath("shipped")
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def load_challenge(ref: str | Path) -> Challenge:
    """A shipped challenge by name, or a challenge file by path."""
    text = str(ref)
    if text in challenge_names():
        entry = resources.files(__package__).joinpath("shipped").joinpath(f"{text}.toml")
        return parse_challenge(entry.read_text(encoding="utf-8"), source=f"{text}.toml")
    path = Path(ref)
    if path.suffix.lower() != ".toml":
        names = ", ".join(challenge_names())
        raise ChallengeError(
            f"no challenge {text!r}: name a shipped one ({names}) or a challenge file (.toml)"
        )
    try:
        content = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise ChallengeError(
            f"cannot read challenge file {text!r}: {exc.strerror or exc}"
        ) from None
    except UnicodeDecodeError:
        raise ChallengeError(f"{text}: challenge files must be UTF-8 text") from None
    return parse_challenge(content, source=str(path), folder=path.parent)


def parse_challenge(text: str, *, source: str, folder: Path | None = None) -> Challenge:
    """A challenge from its TOML ``text``; scene and profile files named in it are found
    relative to ``folder`` (a shipped challenge names shipped ones only)."""
    from ..scenario.reader import TableReader

    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ChallengeError(f"{source}: not valid TOML: {exc}") from None
    try:  # read as a scene file is: every mistake names the file and the key's path
        return _Reader(folder).challenge(TableReader(data, "", source, _TOP))
    except PuckboardError as exc:
        raise ChallengeError(str(exc)) from None


class _Reader:
    """Reads a challenge file's tables (scenario.reader's ``TableReader``s)."""

    def __init__(self, folder: Path | None) -> None:
        self.folder = folder

    def challenge(self, top: TableReader) -> Challenge:
        name = top.string("name", "")
        if not _NAME.match(name):
            top.fail("name", "a short name of letters, digits, '-', '_' or '.'", name)
        factory = top.string("factory", "make_controller")
        if not factory.isidentifier():
            top.fail("factory", "a Python function name", factory)
        practice = self.table(top, "practice", _PRACTICE)
        graded = self.table(top, "graded", _GRADED)
        practice_cells = self.cells(practice, "practice")
        graded_cells = self.cells(graded, "graded")
        episodes = self.whole(graded, "episodes", 10, MAX_EPISODES)
        limits = top.sub("limits", _LIMITS) or _empty(top, "limits")
        longest = max(float(c.parameters.get("duration", c.scene.duration)) for c in graded_cells)
        memory = self.whole(limits, "memory_mib", MEMORY_MIB, 1 << 20, low=0)
        ranking = top.sub("ranking", _RANKING) or _empty(top, "ranking")
        return Challenge(
            name=name,
            title=top.string("title", name),
            description=" ".join(top.string("description", "").split()),
            source=top.source,
            factory=factory,
            practice=practice_cells,
            practice_seeds=self.seeds(practice),
            graded=graded_cells,
            episodes=episodes,
            episode_timeout=limits.number(
                "episode_timeout", longest + 30.0, unit="s", low=1, high=86400
            ),
            check_timeout=limits.number("check_timeout", CHECK_TIMEOUT, unit="s", low=1, high=3600),
            memory_mib=memory or None,
            ranking=self.names(ranking, "order", list(DEFAULT_RANKING), RANKING_KEYS),
            baselines=self.names(ranking, "baselines", [], _shipped_controllers()),
        )

    def table(self, top: TableReader, key: str, keys: Sequence[str]) -> TableReader:
        table = top.sub(key, keys)
        if table is None:
            top.fail(key, "", message=f"missing; a challenge needs [{key}] with [[{key}.cells]]")
        return table  # type: ignore[return-value]

    def whole(self, table: TableReader, key: str, default: int, high: int, low: int = 1) -> int:
        value = table.number(key, default, low=low, high=high)
        if not value.is_integer():
            table.fail(key, "a whole number", value)
        return int(value)

    def seeds(self, practice: TableReader) -> range:
        from ..sweep.plan import PlanError, parse_seeds

        text = practice.string("seeds", "0:3")
        try:
            seeds = parse_seeds(text)
        except PlanError as exc:
            practice.fail("seeds", "", message=str(exc).replace("--seeds ", ""))
        if len(seeds) > MAX_EPISODES:
            practice.fail("seeds", f"at most {MAX_EPISODES} seeds", text)
        return seeds

    def names(
        self, table: TableReader, key: str, default: list[str], known: Collection[str]
    ) -> tuple[str, ...]:
        value = table.raw(key) if table.has(key) else default
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            table.fail(key, f"a list of names ({', '.join(known)})", value)
        for item in value:
            if item not in known:
                table.fail(key, "", message=f"unknown name {item!r}; use {', '.join(known)}")
        if len(set(value)) != len(value):
            table.fail(key, "", message="a name is listed twice")
        if key == "order" and not value:
            table.fail(key, f"at least one of {', '.join(known)}", value)
        return tuple(value)

    def cells(self, table: TableReader, which: str) -> tuple[Cell, ...]:
        cells = [self.cell(reader) for reader in table.items("cells", _CELL)]
        if not cells:
            table.fail("cells", "", message=f"missing; give at least one [[{which}.cells]]")
        from ..scenario.reader import unique_names

        unique_names([c.name for c in cells], f"{which}.cells", table.source)
        seen: dict[str, str] = {}
        for cell in cells:
            settings = {k: v for k, v in cell.parameters.items() if k != "label.cell"}
            same = json.dumps([cell.scene.name, _plain(settings)])
            if same in seen:
                table.fail(
                    "cells", "", message=f"cells {seen[same]!r} and {cell.name!r} are the same cell"
                )
            seen[same] = cell.name
        return tuple(cells)

    def cell(self, table: TableReader) -> Cell:
        from ..profile.links import link_names
        from ..scenario.scenefile import load_scene
        from ..scenario.settings import CONTROL_LATENCY, CONTROL_PERIOD
        from ..scenario.variation import variation_names
        from ..sweep.plan import PlanError, SweepPlan, check_parameter

        name = table.string("name")
        if not name.strip() or len(name) > 40:
            table.fail("name", "a short text (at most 40 characters)", name)
        try:
            scene = load_scene(self.path(table.string("scene")))
        except (PuckboardError, ValueError, OSError) as exc:
            table.fail("scene", "", message=str(exc))
        parameters: dict[str, Any] = {"label.cell": name}
        if table.has("profile"):
            parameters.update(self.profile(table))
        variation = table.string("variation", "none", choices=tuple(variation_names()))
        if variation != "none":
            parameters["variation"] = variation
        if table.has("duration"):
            parameters["duration"] = table.number(
                "duration", unit="s", low=0, low_open=True, high=3600
            )
        settings = table.sub("set")
        for key in settings.data if settings is not None else ():
            try:
                check_parameter(key)
            except PlanError as exc:
                settings.fail(key, "", message=str(exc))  # type: ignore[union-attr]
            if key in ("duration", "variation", "robot.profile") or key.startswith(
                ("label.", "profile.")
            ):
                settings.fail(key, "", message=f"give {key} as the cell's own key")  # type: ignore[union-attr]
            parameters[key] = settings.raw(key)  # type: ignore[union-attr]
        if table.has("link"):
            if any(s.name in parameters for s in (CONTROL_PERIOD, CONTROL_LATENCY)):
                table.fail(
                    "link", "", message="give either link or set control.period / control.latency"
                )
            link = table.string("link", choices=tuple(link_names()))
            parameters.update(self.link(link, scene, parameters))
        try:  # what a sweep would refuse, refused now
            SweepPlan(scene.name, fixed=parameters, seeds=range(1))
        except PlanError as exc:
            table.fail("set", "", message=str(exc))
        written = {k: table.data[k] for k in _CELL if k in table.data and k != "name"}
        return Cell(name=name, scene=scene, parameters=parameters, written=written)

    def path(self, ref: str) -> str | Path:
        """A scene or profile file named in the file, relative to the file's folder."""
        looks_like_file = ref.endswith((".toml", ".json")) or "/" in ref or "\\" in ref
        if looks_like_file and self.folder is not None and not Path(ref).is_absolute():
            return self.folder / ref
        return ref

    def profile(self, table: TableReader) -> dict[str, Any]:
        from ..profile.files import resolve_profile
        from ..profile.shipped import get_profile
        from ..sweep.plan import profile_parameters

        try:
            chosen = resolve_profile(table.raw("profile"), relative_to=self.folder)
            return profile_parameters(
                get_profile(chosen).name if isinstance(chosen, str) else chosen
            )
        except (PuckboardError, ValueError, OSError) as exc:
            table.fail("profile", "", message=str(exc))
            raise  # unreachable: fail raised

    def link(self, link: str, scene: Scene, parameters: Mapping[str, Any]) -> dict[str, Any]:
        from ..transfer.families import link_timing

        return link_timing(link, float(parameters.get("dt", scene.dt)))


def _empty(top: TableReader, key: str) -> TableReader:
    """An empty table in place of an absent optional one: every value its default."""
    from ..scenario.reader import TableReader

    return TableReader({}, top.where(key), top.source)


def _shipped_controllers() -> tuple[str, ...]:
    from ..behaviours.presets import CONTROLLERS

    return tuple(CONTROLLERS)
