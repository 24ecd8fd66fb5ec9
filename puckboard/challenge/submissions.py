"""A class's submissions: found in a folder, known by their content, kept with their history.

A submission is one Python file defining the challenge's factory
(``make_controller(**params)``): either ``FOLDER/NAME.py``, or the one ``.py`` file of
``FOLDER/NAME/`` (the layout a course site's "download all" gives). Files and folders
whose names start with ``_`` or ``.`` are skipped (keep a reference solution as
``_reference.py``). The name is the submission's; two that would share it are refused.

Each file is known by the SHA-256 of its bytes. A *version* is one content of one
submission (``alice@3f2a9c1d0e``); grading it copies the file into the output folder
(``versions/NAME/DIGEST/FILE``), runs that copy, never the file in the class's folder
(which may change meanwhile), and keeps it: the history (:class:`History`) lists every
version each submission had, when it was first seen, so "latest" and "final" views of
the class can be told apart and re-grading runs only what is new.
"""

from __future__ import annotations

import hashlib
import json
import shutil
from dataclasses import dataclass, replace
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

from ..errors import ChallengeError
from ..recording.atomic import write_atomically

__all__ = ["History", "Submission", "Version", "find_submissions"]


@dataclass(frozen=True)
class Submission:
    """One file of the class's folder, as found now."""

    name: str
    path: Path
    digest: str

    @property
    def version(self) -> str:
        return version_id(self.name, self.digest)


def version_id(name: str, digest: str) -> str:
    """How a version is named in rows and tables: ``NAME@`` and the digest's start."""
    return f"{name}@{digest[:10]}"


def _skipped(path: Path) -> bool:
    return path.name.startswith(("_", "."))


def find_submissions(folder: str | Path) -> list[Submission]:
    """The submissions in ``folder``, by name; one-line errors for a folder that does not
    exist or holds none, a folder holding several files, and names that clash."""
    root = Path(folder)
    if not root.is_dir():
        raise ChallengeError(f"the submissions folder {str(root)!r} does not exist")
    found: dict[str, list[Path]] = {}
    for entry in sorted(root.iterdir()):
        if _skipped(entry):
            continue
        if entry.is_file() and entry.suffix == ".py":
            found.setdefault(entry.stem.casefold(), []).append(entry)
        elif entry.is_dir():
            files = sorted(p for p in entry.glob("*.py") if p.is_file() and not _skipped(p))
            if len(files) > 1:
                names = ", ".join(p.name for p in files)
                raise ChallengeError(
                    f"{entry.as_posix()}/ holds {len(files)} .py files ({names}); a submission "
                    "is one file: keep that one, or name the others with a leading _"
                )
            if files:
                found.setdefault(entry.name.casefold(), []).append(files[0])
    if not found:
        raise ChallengeError(
            f"the submissions folder {str(root)!r} holds no submission: NAME.py files, or "
            "folders holding one .py file each"
        )
    submissions = []
    for paths in found.values():
        if len(paths) > 1:
            shown = " and ".join(str(p.relative_to(root).as_posix()) for p in paths)
            raise ChallengeError(
                f"two submissions have the same name: {shown}; rename one (names are "
                "compared without case, as Windows and macOS compare file names)"
            )
        path = paths[0]
        name = path.stem if path.parent == root else path.parent.name
        digest = hashlib.sha256(path.read_bytes()).hexdigest()
        submissions.append(Submission(name=name, path=path, digest=digest))
    return sorted(submissions, key=lambda s: s.name.casefold())


def _now() -> str:
    return datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


@dataclass(frozen=True)
class Version:
    """One content of one submission, as the history keeps it."""

    name: str
    digest: str
    file: str
    first_seen: str
    #: when its last graded episode had run (``None`` until then)
    graded_at: str | None = None

    @property
    def id(self) -> str:
        return version_id(self.name, self.digest)

    def to_dict(self) -> dict[str, Any]:
        return {
            "digest": self.digest,
            "file": self.file,
            "first_seen": self.first_seen,
            "graded_at": self.graded_at,
        }


class History:
    """Every version of every submission ever graded into one output folder, and the
    frozen final view; kept in ``history.json`` (written atomically)."""

    FILE = "history.json"

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.path = folder / self.FILE
        self.versions: dict[str, list[Version]] = {}
        #: the versions the final ranking counts (name -> digest), once frozen
        self.final: dict[str, str] | None = None
        self.final_at: str | None = None
        if self.path.exists():
            data = json.loads(self.path.read_text(encoding="utf-8"))
            for name, entries in data.get("versions", {}).items():
                self.versions[name] = [Version(name=name, **e) for e in entries]
            self.final = data.get("final")
            self.final_at = data.get("final_at")

    def add(self, submission: Submission) -> tuple[Version, bool]:
        """The version ``submission`` is, recorded (and its file kept) if new: ``(version,
        new)``."""
        known = self.versions.setdefault(submission.name, [])
        for version in known:
            if version.digest == submission.digest:
                return version, False
        version = Version(submission.name, submission.digest, submission.path.name, _now())
        copy = self.file_of(version)
        copy.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(submission.path, copy)
        known.append(version)
        return version, True

    def mark_graded(self, version: Version) -> Version:
        """Note that ``version``'s graded episodes have all run (once: the first time)."""
        known = self.versions[version.name]
        index = next(i for i, v in enumerate(known) if v.digest == version.digest)
        if known[index].graded_at is None:
            known[index] = replace(known[index], graded_at=_now())
        return known[index]

    def file_of(self, version: Version) -> Path:
        """Where the graded copy of ``version`` is kept, under the name it was handed in
        with (what Python's messages about it then show)."""
        return self.folder / "versions" / version.name / version.digest[:16] / version.file

    def latest(self, present: dict[str, str] | None = None) -> dict[str, Version]:
        """Each submission's latest version (``present``: name -> digest of the files in
        the class's folder now, which win where given)."""
        out: dict[str, Version] = {}
        for name, known in self.versions.items():
            if not known:
                continue
            chosen = known[-1]
            if present is not None:
                if name not in present:
                    continue
                chosen = next((v for v in known if v.digest == present[name]), chosen)
            out[name] = chosen
        return out

    def final_versions(self) -> dict[str, Version] | None:
        """The frozen final view (``None`` until frozen)."""
        if self.final is None:
            return None
        out = {}
        for name, digest in self.final.items():
            out[name] = next(v for v in self.versions[name] if v.digest == digest)
        return out

    def freeze(self, versions: dict[str, Version]) -> None:
        """Make ``versions`` the final view, from now on."""
        self.final = {name: v.digest for name, v in versions.items()}
        self.final_at = _now()

    def save(self) -> None:
        data = {
            "versions": {n: [v.to_dict() for v in known] for n, known in self.versions.items()},
            "final": self.final,
            "final_at": self.final_at,
        }
        self.folder.mkdir(parents=True, exist_ok=True)
        write_atomically(self.path, json.dumps(data, indent=1, sort_keys=True).encode("utf-8"))
