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

import difflib
import hashlib
import json
import re
import sys
from collections.abc import Mapping, Sequence
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
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ChallengeError(f"{source}: not valid TOML: {exc}") from None
    return _Reader(source, folder).challenge(data)


class _Reader:
    """Reads one file's tables, every error naming the file and the table."""

    def __init__(self, source: str, folder: Path | None) -> None:
        self.source = source
        self.folder = folder

    def fail(self, where: str, problem: str) -> ChallengeError:
        return ChallengeError(f"{self.source}: {where}: {problem}")

    def keys(self, table: Any, known: Sequence[str], where: str) -> dict[str, Any]:
        if not isinstance(table, dict):
            raise self.fail(where, f"expected a table, got {table!r}")
        for key in table:
            if key not in known:
                close = difflib.get_close_matches(key, known, n=1)
                hint = f" (did you mean {close[0]!r}?)" if close else ""
                raise self.fail(where, f"unknown key {key!r}{hint}; keys: {', '.join(known)}")
        return table

    def number(self, value: Any, where: str, *, low: float, high: float) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.fail(where, f"needs a number, got {value!r}")
        if not low <= value <= high:
            raise self.fail(where, f"must be within {low:g}..{high:g}, got {value!r}")
        return float(value)

    def challenge(self, data: dict[str, Any]) -> Challenge:
        top = self.keys(data, _TOP, "the top level")
        name = top.get("name")
        if not isinstance(name, str) or not _NAME.match(name):
            raise self.fail(
                "name", f"needs a short name of letters, digits, '-', '_' or '.', got {name!r}"
            )
        factory = top.get("factory", "make_controller")
        if not isinstance(factory, str) or not factory.isidentifier():
            raise self.fail("factory", f"needs a Python function name, got {factory!r}")
        practice = self.keys(top.get("practice", {}), _PRACTICE, "[practice]")
        graded = self.keys(top.get("graded"), _GRADED, "[graded]")
        practice_cells = self.cells(practice.get("cells"), "practice")
        graded_cells = self.cells(graded.get("cells"), "graded")
        episodes = int(
            self.number(graded.get("episodes", 10), "[graded] episodes", low=1, high=MAX_EPISODES)
        )
        limits = self.keys(top.get("limits", {}), _LIMITS, "[limits]")
        longest = max(float(c.parameters.get("duration", c.scene.duration)) for c in graded_cells)
        episode_timeout = self.number(
            limits.get("episode_timeout", longest + 30.0),
            "[limits] episode_timeout",
            low=1,
            high=86400,
        )
        check_timeout = self.number(
            limits.get("check_timeout", CHECK_TIMEOUT), "[limits] check_timeout", low=1, high=3600
        )
        memory = limits.get("memory_mib", MEMORY_MIB)
        memory_mib = (
            None
            if memory == 0
            else int(self.number(memory, "[limits] memory_mib", low=0, high=1 << 20))
        )
        ranking = self.keys(top.get("ranking", {}), _RANKING, "[ranking]")
        return Challenge(
            name=name,
            title=str(top.get("title", name)),
            description=str(top.get("description", "")).strip(),
            source=self.source,
            factory=factory,
            practice=practice_cells,
            practice_seeds=self.seeds(practice.get("seeds", "0:3")),
            graded=graded_cells,
            episodes=episodes,
            episode_timeout=episode_timeout,
            check_timeout=check_timeout,
            memory_mib=memory_mib,
            ranking=self.order(ranking.get("order", list(DEFAULT_RANKING))),
            baselines=self.baselines(ranking.get("baselines", [])),
        )

    def seeds(self, value: Any) -> range:
        from ..sweep.plan import PlanError, parse_seeds

        if not isinstance(value, str):
            raise self.fail("[practice] seeds", f'needs a range as text, e.g. "0:3", got {value!r}')
        try:
            seeds = parse_seeds(value)
        except PlanError as exc:
            raise self.fail("[practice] seeds", str(exc).replace("--seeds ", "")) from None
        if len(seeds) > MAX_EPISODES:
            raise self.fail("[practice] seeds", f"at most {MAX_EPISODES} seeds, got {len(seeds)}")
        return seeds

    def order(self, value: Any) -> tuple[str, ...]:
        where = "[ranking] order"
        if not isinstance(value, list) or not value:
            raise self.fail(where, f"needs a list of {', '.join(RANKING_KEYS)}, got {value!r}")
        for key in value:
            if key not in RANKING_KEYS:
                raise self.fail(where, f"unknown key {key!r}; use {', '.join(RANKING_KEYS)}")
        if len(set(value)) != len(value):
            raise self.fail(where, "a key is listed twice")
        return tuple(value)

    def baselines(self, value: Any) -> tuple[str, ...]:
        from ..behaviours.presets import CONTROLLERS

        where = "[ranking] baselines"
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            raise self.fail(where, f"needs a list of shipped controllers, got {value!r}")
        for spec in value:
            if spec not in CONTROLLERS:
                raise self.fail(
                    where, f"{spec!r} is not a shipped controller; use {', '.join(CONTROLLERS)}"
                )
        if len(set(value)) != len(value):
            raise self.fail(where, "a baseline is listed twice")
        return tuple(value)

    def cells(self, value: Any, which: str) -> tuple[Cell, ...]:
        if not isinstance(value, list) or not value:
            raise self.fail(
                f"[{which}]", f"needs at least one cell: [[{which}.cells]] with a name and a scene"
            )
        cells = [self.cell(entry, f"[[{which}.cells]] {i}") for i, entry in enumerate(value, 1)]
        names = [c.name for c in cells]
        for name in names:
            if names.count(name) > 1:
                raise self.fail(f"[[{which}.cells]]", f"two cells are named {name!r}")
        seen: dict[str, str] = {}
        for cell in cells:
            same = json.dumps(
                [
                    cell.scene.name,
                    _plain({k: v for k, v in cell.parameters.items() if k != "label.cell"}),
                ]
            )
            if same in seen:
                raise self.fail(
                    f"[[{which}.cells]]",
                    f"cells {seen[same]!r} and {cell.name!r} are the same cell",
                )
            seen[same] = cell.name
        return tuple(cells)

    def cell(self, entry: Any, where: str) -> Cell:
        from ..scenario.scenefile import load_scene
        from ..sweep.plan import PlanError, SweepPlan, check_parameter, profile_parameters

        table = self.keys(entry, _CELL, where)
        name = table.get("name")
        if not isinstance(name, str) or not name.strip() or len(name) > 40:
            raise self.fail(where, f"name needs a short text (at most 40 characters), got {name!r}")
        where = f"{where} ({name!r})"
        scene_ref = table.get("scene")
        if not isinstance(scene_ref, str):
            raise self.fail(
                where, f"scene needs a shipped scene name or a scene file, got {scene_ref!r}"
            )
        try:
            scene = load_scene(self.path(scene_ref))
        except (PuckboardError, ValueError, OSError) as exc:
            raise self.fail(where, str(exc)) from None
        parameters: dict[str, Any] = {"label.cell": name}
        if table.get("profile") is not None:
            parameters.update(self.profile(table["profile"], where, profile_parameters))
        variation = table.get("variation", "none")
        from ..profile import VARIATIONS

        if variation not in VARIATIONS:
            raise self.fail(where, f"variation {variation!r} is not one of {', '.join(VARIATIONS)}")
        if variation != "none":
            parameters["variation"] = variation
        if table.get("duration") is not None:
            parameters["duration"] = self.number(
                table["duration"], f"{where}: duration", low=0.05, high=3600
            )
        settings = table.get("set", {})
        if not isinstance(settings, dict):
            raise self.fail(where, f"set needs a table of parameters, got {settings!r}")
        for key, value in settings.items():
            try:
                check_parameter(key)
            except PlanError as exc:
                raise self.fail(where, f"set: {exc}") from None
            if key in ("duration", "variation", "robot.profile") or key.startswith(
                ("label.", "profile.")
            ):
                raise self.fail(where, f"set: give {key} as the cell's own key, not in set")
            parameters[key] = value
        if table.get("link") is not None:
            parameters.update(self.link(table["link"], where, scene, parameters))
        try:  # what a sweep would refuse, refused now
            SweepPlan(scene.name, fixed=parameters, seeds=range(1))
        except PlanError as exc:
            raise self.fail(where, str(exc)) from None
        written = {k: table[k] for k in _CELL if k in table and k != "name"}
        return Cell(name=name, scene=scene, parameters=parameters, written=written)

    def path(self, ref: str) -> str | Path:
        """A scene or profile file named in the file, relative to the file's folder."""
        looks_like_file = ref.endswith((".toml", ".json")) or "/" in ref or "\\" in ref
        if looks_like_file and self.folder is not None and not Path(ref).is_absolute():
            return self.folder / ref
        return ref

    def profile(self, value: Any, where: str, parameters: Any) -> dict[str, Any]:
        from ..profile.files import resolve_profile
        from ..profile.shipped import get_profile

        try:
            chosen = resolve_profile(value, relative_to=self.folder)
            profile = get_profile(chosen).name if isinstance(chosen, str) else chosen
            return dict(parameters(profile))
        except (PuckboardError, ValueError, OSError) as exc:
            raise self.fail(where, f"profile: {exc}") from None

    def link(
        self, value: Any, where: str, scene: Scene, parameters: Mapping[str, Any]
    ) -> dict[str, Any]:
        from ..profile.links import link_names
        from ..transfer.families import link_timing

        if value not in link_names():
            raise self.fail(where, f"link {value!r} is not one of {', '.join(link_names())}")
        if any(k in parameters for k in ("control.period", "control.latency")):
            raise self.fail(where, "give either link or set control.period / control.latency")
        return link_timing(value, float(parameters.get("dt", scene.dt)))
