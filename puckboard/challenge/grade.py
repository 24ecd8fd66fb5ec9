"""Grade a class: every submission checked and run on the graded cells, in processes of its
own, resumably, and the leaderboard made from what the output folder holds.

:func:`grade` is what ``puckboard challenge grade`` does::

    folder --(new or changed files, by content)--> versions --pre-flight--> checked
           --graded cells x secret seeds (run_sweeps, one isolation each)--> episodes.csv
           --> standings (latest, final) --> replays, leaderboard.html, results.csv

Each submission's version runs in worker processes of its own
(:class:`~puckboard.sweep.host.Isolation`): never beside another student's code or the
grading process, which holds the secret and the results. The process is killed when an
episode runs past the challenge's wall-clock limit, or its pre-flight check past its
own; whatever a submission does, it ends as a verdict on its own row and the class is
graded. Every finished episode is on disk at once; after Ctrl-C or ``kill -9`` the same
command resumes, and a re-grade runs only versions (or baselines) not graded yet.
"""

from __future__ import annotations

import logging
import time
from collections import Counter
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..sweep.executors import LocalExecutor, SweepExecutor
from ..sweep.host import Isolation
from ..sweep.options import RunOptions
from ..sweep.plan import SweepPlan
from ..sweep.progress import NullProgress, Progress
from ..sweep.rows import Outcome
from ..sweep.run import drain, run_sweeps
from ..sweep.signals import Terminated
from .outputs import Outputs, SealedStore
from .result import Grading
from .standings import Standing, rank, summarise_entry, verdict_of
from .submissions import History, Version, find_submissions
from .tasks import TIMED_TICKS, preflight, replay

if TYPE_CHECKING:
    from .seeds import Secret
    from .spec import Challenge

__all__ = ["FILE_LIMIT", "Grading", "grade"]

log = logging.getLogger(__name__)

#: The largest file a submission's process may write (its printed output included).
FILE_LIMIT = 16 * 1024 * 1024


def grade(
    challenge: Challenge,
    folder: str | Path,
    secret: Secret,
    out: str | Path,
    *,
    executor: SweepExecutor | None = None,
    progress: Progress | None = None,
    reveal: bool = False,
    final: bool = False,
) -> Grading:
    """Grade the submissions in ``folder`` on ``challenge`` into the output folder ``out``
    (see the module docstring); ``final`` freezes the final view on this run's versions,
    ``reveal`` (after the deadline) freezes it if not yet frozen and shows the seeds."""
    t0 = time.perf_counter()
    submissions = find_submissions(folder)  # a bad folder is refused before anything changes
    outputs = Outputs(Path(out))
    outputs.open(challenge.identity(), secret.check())
    history = History(outputs.folder)
    new = []
    for submission in submissions:
        version, fresh = history.add(submission)
        if fresh:
            new.append(version.id)
    history.save()
    present = {s.name: s.digest for s in submissions}
    latest = history.latest(present)
    frozen = history.final_versions() or {}
    versions = {v.id: v for v in [*latest.values(), *frozen.values()]}
    seeds = secret.graded_seeds(challenge)
    run = _Run(challenge, outputs, history, versions, seeds)
    own = executor is None
    executor = executor or LocalExecutor()
    stopped: KeyboardInterrupt | None = None
    steps = {
        "check": lambda: run.check(executor),
        "episodes": lambda: run.episodes(executor, progress or NullProgress()),
        "replays": lambda: run.replays(executor),
    }
    phase_s: dict[str, float] = {}
    try:
        for name, step in steps.items():
            started = time.perf_counter()
            stopped = step()
            phase_s[name] = time.perf_counter() - started
            if stopped is not None:
                break
    finally:
        if own:
            executor.close()
    if final or (reveal and history.final is None):
        history.freeze(history.latest(present))
    if reveal:
        outputs.reveal()
    grading = run.standings(latest, history)
    history.save()  # with when each version's grading finished
    grading.new = new
    grading.phase_s = phase_s
    grading.interrupted = stopped is not None
    grading.terminated = isinstance(stopped, Terminated)
    grading.seeds = seeds if outputs.revealed else None
    grading.revealed_at = outputs.state.get("revealed_at")
    from .leaderboard import write_outputs

    write_outputs(grading, outputs, run.rows, seeds)
    grading.wall_s = time.perf_counter() - t0
    return grading


class _Run:
    """One grading's steps, sharing what they learn."""

    def __init__(
        self,
        challenge: Challenge,
        outputs: Outputs,
        history: History,
        versions: Mapping[str, Version],
        seeds: Mapping[str, tuple[int, ...]],
    ) -> None:
        self.challenge = challenge
        self.outputs = outputs
        self.history = history
        self.versions = dict(versions)
        self.seeds = dict(seeds)
        self.store = SealedStore(outputs.episodes, seeds)
        self.rows: list[dict[str, Any]] = []
        self.checked = 0
        self.ran = 0
        self.skipped = 0

    # -- what runs where -----------------------------------------------------------------
    def spec(self, version: Version) -> str:
        path = self.history.file_of(version).resolve()
        return f"{path.as_posix()}:{self.challenge.factory}"

    def isolation(self, entry: str) -> Isolation | None:
        """A version's processes: its own folder, output file and limits; a baseline
        (shipped code) runs on shared workers."""
        version = self.versions.get(entry)
        if version is None:
            return None
        memory = self.challenge.memory_mib
        return Isolation(
            name=version.id,
            workdir=str(self.outputs.workdir(version.name) / version.digest[:16]),
            output=str(self.outputs.output_file(version.id)),
            memory_bytes=None if memory is None else memory * 1024 * 1024,
            file_bytes=FILE_LIMIT,
        )

    # -- steps ---------------------------------------------------------------------------
    def check(self, executor: SweepExecutor) -> KeyboardInterrupt | None:
        """Each version's pre-flight check, unless one is on file for its content."""
        todo = [v for v in self.versions.values() if v.digest not in self.outputs.checks]
        if not todo:
            return None
        for version in todo:
            self.outputs.workdir(version.name).mkdir(parents=True, exist_ok=True)
            self.outputs.output_file(version.id).parent.mkdir(parents=True, exist_ok=True)
        cell = self.challenge.practice[0]
        seed = self.challenge.practice_seeds[0]
        specs = {self.spec(v): v for v in todo}
        tasks = [
            (spec, self.challenge.factory, cell.scene, dict(cell.parameters), seed, TIMED_TICKS)
            for spec in specs
        ]

        def collect(values: list[dict[str, Any]]) -> None:
            for value in values:
                version = specs[str(value["spec"])]
                self.outputs.save_check(version.digest, value)
                self.checked += 1

        return drain(
            executor,
            lambda: executor.run(
                preflight,
                tasks,
                isolation=[self.isolation(specs[t[0]].id) for t in tasks],
                unit_limit=self.challenge.check_timeout,
            ),
            collect,
        )

    def gradable(self) -> list[str]:
        """The entries whose graded episodes run: checked versions, then the baselines."""
        ok = [
            v.id
            for v in self.versions.values()
            if self.outputs.checks.get(v.digest, {}).get("verdict") == "ok"
        ]
        return sorted(ok, key=str.casefold) + list(self.challenge.baselines)

    def episodes(self, executor: SweepExecutor, progress: Progress) -> KeyboardInterrupt | None:
        entries = self.gradable()
        if not entries:
            return None
        parts = [
            (
                SweepPlan(
                    cell.scene.name,
                    controllers=tuple(entries),
                    seeds=self.seeds[cell.name],
                    fixed=dict(cell.parameters),
                ),
                cell.scene,
            )
            for cell in self.challenge.graded
        ]
        options = RunOptions(
            executor=executor,
            store=self.store,
            progress=progress,
            episode_timeout=self.challenge.episode_timeout,
        )
        results = run_sweeps(
            parts,
            options,
            isolation=self.isolation,
            aliases={v.id: self.spec(v) for v in self.versions.values()},
        )
        self.ran = sum(r.ran for r in results)
        self.skipped = sum(r.skipped for r in results)
        if any(r.interrupted for r in results):
            return Terminated() if any(r.terminated for r in results) else KeyboardInterrupt()
        return None

    def graded_rows(self) -> dict[str, dict[str, list[dict[str, Any]]]]:
        """The stored rows of this grading, by entry and cell (each cell's in episode order)."""
        import json

        cells = {c.name for c in self.challenge.graded}
        by: dict[str, dict[str, list[dict[str, Any]]]] = {}
        self.rows = self.store.rows()
        for row in self.rows:
            cell = json.loads(str(row["params"])).get("label.cell")
            if cell in cells:
                by.setdefault(str(row["controller"]), {}).setdefault(cell, []).append(row)
        for entry in by.values():
            for cell, rows in entry.items():
                order = {seed: i for i, seed in enumerate(self.seeds[cell])}
                rows.sort(key=lambda r: order.get(int(r["seed"]), 0))
        return by

    def replays(self, executor: SweepExecutor) -> KeyboardInterrupt | None:
        """The replays of each complete entry's worst graded run and of one success, as
        offline pages, made once (an entry's episodes never change)."""
        by = self.graded_rows()
        planned = len(self.challenge.graded) * self.challenge.episodes
        tasks = []
        isolations = []
        for entry, cells in by.items():
            if sum(len(r) for r in cells.values()) < planned:
                continue
            for which, row in _replay_choices(self.challenge, cells).items():
                path = self.outputs.replay_file(_entry_file(entry), which)
                if path.exists() or row is None:
                    continue
                cell = self.challenge.cell(_cell_of(row))
                seed = int(row["seed"])
                index = self.seeds[cell.name].index(seed)
                version = self.versions.get(entry)
                name = version.name if version is not None else entry
                title = f"{name} · {cell.name} · graded episode {index + 1} ({which})"
                spec = self.spec(version) if version is not None else entry
                params = dict(cell.parameters)
                tasks.append((cell.scene, spec, seed, params, title, cell.describe(), str(path)))
                isolations.append(self.isolation(entry))
        if not tasks:
            return None
        from ..web.export import write_replay_html
        from .leaderboard import seed_free

        def collect(values: list[dict[str, Any]]) -> None:
            for value in values:
                data = value["data"]
                if data is not None and seed_free(data, self.seeds):
                    path = Path(value["tag"])
                    path.parent.mkdir(parents=True, exist_ok=True)
                    write_replay_html(data, path)

        return drain(
            executor,
            lambda: executor.run(
                replay, tasks, isolation=isolations, unit_limit=self.challenge.episode_timeout
            ),
            collect,
        )

    # -- the leaderboard -----------------------------------------------------------------
    def standings(self, latest: Mapping[str, Version], history: History) -> Grading:
        by = self.graded_rows()
        views = {"latest": self._view(latest, history, by)}
        frozen = history.final_versions()
        if frozen is not None:
            views["final"] = self._view(frozen, history, by)
        lead = "final" if frozen is not None else "latest"
        other = views["latest"] if lead == "final" and _differs(views) else None
        return Grading(
            challenge=self.challenge,
            out=self.outputs.folder,
            view=lead,
            standings=views[lead],
            latest=other,
            final_at=history.final_at,
            checked=self.checked,
            ran=self.ran,
            skipped=self.skipped,
        )

    def _view(
        self,
        versions: Mapping[str, Version],
        history: History,
        by: Mapping[str, Mapping[str, Sequence[dict[str, Any]]]],
    ) -> list[Standing]:
        cells = [c.name for c in self.challenge.graded]
        planned = len(cells) * self.challenge.episodes
        standings = []
        entries: list[tuple[str, Version | None]] = [(v.id, v) for v in versions.values()]
        entries += [(b, None) for b in self.challenge.baselines]
        for entry, version in entries:
            rows = by.get(entry, {})
            outcomes = {cell: [Outcome.from_row(r) for r in rows.get(cell, ())] for cell in cells}
            standing = Standing(
                name=version.name if version else entry, baseline=version is None, planned=planned
            )
            if version is not None:
                standing.version = version.id
                standing.file = version.file
                standing.first_seen = version.first_seen
            summarise_entry(standing, cells, outcomes)
            errors = Counter(
                o.error_kind for os_ in outcomes.values() for o in os_ if o.failure == "error"
            )
            check = self.outputs.checks.get(version.digest) if version is not None else None
            standing.verdict, standing.verdict_text = verdict_of(
                standing, check, errors, self.challenge.episode_timeout
            )
            if check is not None:
                standing.details = str(check.get("details") or "")
            if version is not None and standing.complete:
                version = history.mark_graded(version)
                standing.graded_at = version.graded_at
            standing.remarks = self._remarks(version, check)
            for which in ("worst", "success"):
                path = self.outputs.replay_file(_entry_file(entry), which)
                if path.exists():
                    standing.replays[which] = path.relative_to(self.outputs.folder).as_posix()
            standings.append(standing)
        return rank(standings, self.challenge.ranking)

    def _remarks(self, version: Version | None, check: Mapping[str, Any] | None) -> list[str]:
        """What else a version did: printed, wrote files, ticked slower than its period."""
        if version is None:
            return []
        remarks = []
        output = self.outputs.output_file(version.id)
        if output.exists() and output.stat().st_size:  # how much depends on how often it ran
            remarks.append("printed to its output file")
        work = self.outputs.workdir(version.name) / version.digest[:16]
        if work.is_dir():
            files = sorted(p.relative_to(work).as_posix() for p in work.rglob("*") if p.is_file())
            if files:
                shown = ", ".join(files[:3]) + (
                    f" and {len(files) - 3} more" if len(files) > 3 else ""
                )
                remarks.append(f"wrote {shown}")
        ticks = (check or {}).get("ticks") or {}
        period = ticks.get("period_s")
        if period and ticks.get("p95_s", 0.0) > period:
            remarks.append(
                f"ticks took up to {1e3 * ticks['p95_s']:.0f} ms, over the {1e3 * period:.0f} ms "
                "control period"
            )
        return remarks


def _differs(views: Mapping[str, list[Standing]]) -> bool:
    def shape(standings: list[Standing]) -> list[Any]:
        return [(s.name, s.version) for s in standings]

    return shape(views["latest"]) != shape(views["final"])


def _cell_of(row: Mapping[str, Any]) -> str:
    import json

    return str(json.loads(str(row["params"])).get("label.cell"))


def _entry_file(entry: str) -> str:
    """An entry as a file name's start: a version id as it is, a baseline by its name."""
    return entry if "@" in entry else f"baseline-{entry}"


def _replay_choices(
    challenge: Challenge, cells: Mapping[str, Sequence[Mapping[str, Any]]]
) -> dict[str, Mapping[str, Any] | None]:
    """The entry's worst graded run (the failure of least progress that was not an error:
    an error episode would end the same way again) and its first success, in cell order."""
    rows = [r for cell in challenge.graded for r in cells.get(cell.name, ())]

    def succeeded(row: Mapping[str, Any]) -> bool:
        return str(row.get("success")).lower() in ("true", "1")

    failures = [r for r in rows if not succeeded(r) and not r.get("error")]
    worst = min(failures, key=lambda r: float(r.get("progress_laps") or 0.0), default=None)
    success = next((r for r in rows if succeeded(r)), None)
    return {"worst": worst, "success": success}
