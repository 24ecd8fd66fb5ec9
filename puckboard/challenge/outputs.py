"""A grading's output folder: what it holds, and how nothing in it names a graded seed.

``--out DIR`` holds everything one challenge's grading keeps, so that the same command
resumes it after Ctrl-C or ``kill -9`` and re-grades only what changed:

* ``challenge.json`` — which challenge (its identity, :meth:`Challenge.identity`) and
  which secret (a tag, :meth:`Secret.check`) the results are of, and whether the seeds
  were revealed; another challenge or secret is refused, naming the difference;
* ``history.json`` and ``versions/`` — every version of every submission, kept
  (:class:`~puckboard.challenge.submissions.History`);
* ``checks.json`` — each version's pre-flight check, by content digest;
* ``episodes.csv`` — one row per graded episode (the sweep's rows, :mod:`puckboard.sweep.rows`),
  appended as episodes finish: :class:`SealedStore` keeps the seed out of them;
* ``work/NAME/`` and ``output/VERSION.txt`` — the folder each submission runs in, and
  what it printed;
* ``replays/`` and ``leaderboard.html``, ``results.csv`` — what is published.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

from ..errors import ChallengeError
from ..recording.atomic import write_atomically
from ..sweep.plan import episode_key
from ..sweep.store import CsvStore, ResultStore

__all__ = ["Outputs", "SealedStore", "write_json"]

#: Version of the folder's layout.
FORMAT = 1


def write_json(path: Path, data: Any) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    write_atomically(path, (json.dumps(data, indent=1, sort_keys=True) + "\n").encode("utf-8"))


def now() -> str:
    return datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


class SealedStore(ResultStore):
    """The graded episodes' rows, stored without their seeds.

    A row is written with an empty ``seed`` and its index within its cell in
    ``episode``, and a key made with that index in place of the seed; read back, each
    gets its seed and its real key again from ``seeds`` (cell name → that cell's seeds),
    so the sweep resumes as from any store. Without the secret the file says which
    episode of which cell a row is, never its seed.
    """

    def __init__(self, path: Path, seeds: Mapping[str, tuple[int, ...]]) -> None:
        super().__init__(path)
        self._inner = CsvStore(path)
        self._seeds = {cell: list(values) for cell, values in seeds.items()}

    def _cell(self, row: Mapping[str, Any]) -> str:
        params = row.get("params")
        data = json.loads(params) if isinstance(params, str) else dict(params or {})
        return str(data.get("label.cell", ""))

    def append(self, rows: Iterable[Mapping[str, Any]]) -> None:
        sealed = []
        for row in rows:
            cell = self._cell(row)
            index = self._seeds[cell].index(int(row["seed"]))
            params = json.loads(str(row["params"]))
            out = dict(row)
            out["key"] = episode_key(str(row["scenario"]), str(row["controller"]), index, params)
            out["seed"] = ""
            out["episode"] = index
            sealed.append(out)
        self._inner.append(sealed)

    def rows(self) -> list[dict[str, Any]]:
        out = []
        for row in self._inner.rows():
            cell = self._cell(row)
            if cell not in self._seeds or not str(row.get("episode", "")).isdigit():
                continue  # a cell no longer graded: not this grading's row
            index = int(row["episode"])
            if index >= len(self._seeds[cell]):
                continue
            seed = self._seeds[cell][index]
            params = json.loads(str(row["params"]))
            unsealed = dict(row)
            unsealed["seed"] = seed
            unsealed["key"] = episode_key(
                str(row["scenario"]), str(row["controller"]), seed, params
            )
            out.append(unsealed)
        return out

    def flush(self) -> None:
        self._inner.flush()


class Outputs:
    """The output folder of one challenge's grading; see the module docstring."""

    def __init__(self, folder: Path) -> None:
        #: as given (for messages); every path below is absolute, as a worker needs it
        self.given = folder
        self.folder = folder.resolve()
        self.state_path = folder / "challenge.json"
        self.checks_path = folder / "checks.json"
        self.episodes = folder / "episodes.csv"
        self.leaderboard = folder / "leaderboard.html"
        self.results = folder / "results.csv"
        self.state: dict[str, Any] = {}
        self.checks: dict[str, dict[str, Any]] = {}

    def open(self, identity: Mapping[str, Any], secret_check: str) -> None:
        """Take the folder for this challenge and secret, or refuse it in one line when
        it holds another's results (or is no grading's folder)."""
        folder = self.folder
        if folder.exists() and not folder.is_dir():
            raise ChallengeError(f"--out {str(self.given)!r} is a file; name a folder")
        if self.state_path.exists():
            try:
                self.state = json.loads(self.state_path.read_text(encoding="utf-8"))
            except (OSError, ValueError) as exc:
                raise ChallengeError(
                    f"--out {str(folder)!r}: cannot read challenge.json: {exc}"
                ) from None
            self._check_same(identity, secret_check)
        elif folder.exists() and any(folder.iterdir()):
            raise ChallengeError(
                f"--out {str(self.given)!r} holds files but no grading (no challenge.json); name "
                "an empty or new folder"
            )
        else:
            self.state = {
                "format": FORMAT,
                "identity": dict(identity),
                "secret_check": secret_check,
                "revealed_at": None,
                "started": now(),
            }
            write_json(self.state_path, self.state)
        if self.checks_path.exists():
            self.checks = json.loads(self.checks_path.read_text(encoding="utf-8"))

    def _check_same(self, identity: Mapping[str, Any], secret_check: str) -> None:
        from .spec import identity_differences

        differences = identity_differences(identity, self.state.get("identity") or {})
        where = f"--out {str(self.given)!r}"
        if differences:
            raise ChallengeError(
                f"{where} holds the results of another challenge ({'; '.join(differences)}); "
                "name another folder, or grade that challenge"
            )
        if self.state.get("secret_check") != secret_check:
            raise ChallengeError(
                f"{where} was graded with another secret (the same secret gives the same "
                "seeds); give that secret, or name another folder"
            )

    @property
    def revealed(self) -> bool:
        return bool(self.state.get("revealed_at"))

    def reveal(self) -> None:
        if not self.revealed:
            self.state["revealed_at"] = now()
            write_json(self.state_path, self.state)

    def save_check(self, digest: str, result: Mapping[str, Any]) -> None:
        self.checks[digest] = dict(result)
        write_json(self.checks_path, self.checks)

    def workdir(self, name: str) -> Path:
        return self.folder / "work" / name

    def output_file(self, version: str) -> Path:
        return self.folder / "output" / f"{version}.txt"

    def replay_file(self, version: str, which: str) -> Path:
        return self.folder / "replays" / f"{version}-{which}.html"
