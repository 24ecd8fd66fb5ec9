"""Where a study lives between runs: an Optuna journal file.

``--study FILE`` keeps every finished trial in an append-only journal file
(:class:`optuna.storages.JournalStorage` with a file backend). A journal, not SQLite
through Optuna's RDB storage, because it needs nothing beyond Optuna itself (the RDB
storage needs SQLAlchemy and, for SQLite, a database driver on every system), no server,
and its lock is a plain file created exclusively (:class:`JournalFileOpenLock`), which
works alike on Windows, macOS and Linux, where symbolic links (the other lock) may need
rights a student lacks. Every trial is one line appended when it ends, so a Ctrl-C loses
at most the trial that was running.

The study remembers the command that made it (:data:`COMMAND_ATTR`): scenes, controller,
parameters, profiles, seeds and fixed settings. Resuming with another command would mix
trials scored on different episodes, so it is refused (:class:`StudyMismatch`) with the
field that differs. The parameters are compared as a set: the same ``--param`` given in
another order is the same study (it is then drawn in the order that made it).

A journal damaged outside Optuna (a copy cut short, a disk that filled up) is read
here before Optuna opens it, so that nothing is appended to it: a line cut short would
otherwise have the next trial written after it, and the whole file become unreadable.
The message says how many finished trials the whole lines before the damage hold.
"""

from __future__ import annotations

import json
import tempfile
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from optuna.pruners import BasePruner
    from optuna.samplers import BaseSampler
    from optuna.study import Study
    from optuna.trial import FrozenTrial

__all__ = ["COMMAND_ATTR", "STUDY_NAME", "StudyMismatch", "finished_trials", "open_study"]

#: The study's name inside its file (one study per file).
STUDY_NAME = "puckboard-tune"
#: User attribute holding the command that made the study.
COMMAND_ATTR = "puckboard.command"


class StudyMismatch(ValueError):
    """A study file made by another command (or not a study file at all)."""


def _quiet_optuna() -> Any:
    import optuna

    optuna.logging.set_verbosity(optuna.logging.WARNING)  # no line per trial: ours say more
    warnings.filterwarnings("ignore", category=optuna.exceptions.ExperimentalWarning)
    return optuna


def open_study(
    path: Path | None, command: Mapping[str, Any], *, sampler: BaseSampler, pruner: BasePruner
) -> Study:
    """The study in ``path`` (created when missing; in memory without ``path``), checked
    to have been made by ``command``."""
    optuna = _quiet_optuna()
    from optuna.storages.journal import JournalFileBackend, JournalFileOpenLock

    storage: Any = None
    if path is not None and path.is_file():
        _check_whole(path)
    try:
        if path is not None:
            backend = JournalFileBackend(str(path), lock_obj=JournalFileOpenLock(str(path)))
            storage = optuna.storages.JournalStorage(backend)
        study = optuna.create_study(
            study_name=STUDY_NAME,
            storage=storage,
            direction="maximize",
            sampler=sampler,
            pruner=pruner,
            load_if_exists=True,
        )
    except Exception as exc:  # a file of something else: the journal's errors vary
        raise StudyMismatch(
            f"--study {str(path)!r} is not a study file ({type(exc).__name__}); give a new "
            "file name or the file an earlier puckboard tune wrote"
        ) from None
    wanted = json.loads(json.dumps(dict(command)))  # as it reads back from the file
    made_by = study.user_attrs.get(COMMAND_ATTR)
    if made_by is None:
        if study.trials:
            raise StudyMismatch(
                f"--study {str(path)!r} holds a study that puckboard tune did not make; "
                "give a new file name"
            )
        study.set_user_attr(COMMAND_ATTR, wanted)
    elif _comparable(made_by) != _comparable(wanted):
        raise StudyMismatch(_difference(path, made_by, wanted))
    return study


def _comparable(command: Mapping[str, Any]) -> dict[str, Any]:
    """The command with its parameters as a set (their order draws nothing different)."""
    params = command.get("params")
    return {**command, "params": sorted(params) if isinstance(params, list) else params}


def _difference(path: Path | None, made_by: Mapping[str, Any], wanted: Mapping[str, Any]) -> str:
    made, now = _comparable(made_by), _comparable(wanted)
    differ = [k for k in sorted(set(made) | set(now)) if made.get(k) != now.get(k)]
    field = differ[0] if differ else "?"
    return (
        f"--study {str(path)!r} was made by another command ({field}: "
        f"{json.dumps(made_by.get(field))} there, {json.dumps(wanted.get(field))} now); "
        "give a new file name, or the command that made it to resume"
    )


def _check_whole(path: Path) -> None:
    """Refuse a file whose first line is no journal entry (no study file), and a journal
    with a line that is cut short or not JSON, saying what the whole lines before it
    hold. Optuna would read such a file as far as it goes and append after the damage."""
    data = path.read_bytes()
    lines = data.splitlines(keepends=True)
    for number, line in enumerate(lines):
        try:
            entry = json.loads(line)
        except ValueError:
            entry = None
        journal = isinstance(entry, dict) and "op_code" in entry
        if number == 0 and not journal and not line.startswith(b'{"op_code"'):
            raise StudyMismatch(
                f"--study {str(path)!r} is not a study file (its first line is no journal "
                "entry); give a new file name or the file an earlier puckboard tune wrote"
            )
        if journal and line.endswith(b"\n"):
            continue
        kept = _finished_in(b"".join(lines[:number])) if number else 0
        how = "cut short" if not line.endswith(b"\n") else "not a journal line"
        raise StudyMismatch(
            f"--study {str(path)!r} is damaged: line {number + 1} of {len(lines)} is {how}; "
            f"the {number} whole lines before it hold {kept} finished "
            f"trial{'s' if kept != 1 else ''}: to keep them, copy those lines to a new file "
            "and give it as --study; or give a new file name"
        )


def _finished_in(journal: bytes) -> int:
    """Finished trials in the journal text ``journal``, read by Optuna from a copy (a
    temporary file, removed after)."""
    optuna = _quiet_optuna()
    from optuna.storages.journal import JournalFileBackend, JournalFileOpenLock

    with tempfile.TemporaryDirectory() as folder:
        copy = Path(folder) / "whole.journal"
        copy.write_bytes(journal)
        try:
            backend = JournalFileBackend(str(copy), lock_obj=JournalFileOpenLock(str(copy)))
            storage = optuna.storages.JournalStorage(backend)
            study = optuna.load_study(study_name=STUDY_NAME, storage=storage)
            return len(finished_trials(study))
        except Exception:  # the whole lines do not make a study yet
            return 0


def finished_trials(study: Study) -> list[FrozenTrial]:
    """Trials that ended (complete or pruned), in the order they ran: what a resumed
    study skips."""
    from optuna.trial import TrialState

    return study.get_trials(deepcopy=False, states=(TrialState.COMPLETE, TrialState.PRUNED))
