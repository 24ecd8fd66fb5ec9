"""Ctrl-C on a real ``puckboard tune``: the terminal's SIGINT to the whole process group
(parent and workers) once a trial has finished. The command must end with status 130
and one line, no traceback, keep the finished trials in its study, leave no process
behind, and the same command must resume from them. As in tests/sweep/test_interrupts.py,
``EXIT_WITHIN`` is a hang check, not a timing."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
import warnings

import pytest
from process_tree import alive, descendants, require_process_tree

from puckboard.cli import main
from puckboard.tune.storage import STUDY_NAME

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(
        os.name != "posix", reason="signals a process group, as a POSIX terminal does"
    ),
]

EXIT_WITHIN = 15.0
GONE_WITHIN = 5.0
TUNE = [
    "tune", "two-robot-pass", "--controller", "improved",
    "--param", "layer.LineFollow.inner_factor=0.1:0.9", "--seeds", "0:2", "--validate", "2:3",
    "--duration", "3", "--rounds", "1", "--workers", "2", "--quiet",
]  # fmt: skip


def finished(path) -> int:
    import optuna
    from optuna.storages.journal import JournalFileBackend
    from optuna.trial import TrialState

    if not path.exists():
        return 0
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            study = optuna.load_study(
                study_name=STUDY_NAME,
                storage=optuna.storages.JournalStorage(JournalFileBackend(str(path))),
            )
        except KeyError:  # the study is not created yet
            return 0
    return len(study.get_trials(states=(TrialState.COMPLETE, TrialState.PRUNED)))


def test_ctrl_c_keeps_finished_trials_and_the_same_command_resumes(tmp_path, capsys):
    require_process_tree()
    study = tmp_path / "tune.journal"
    args = [*TUNE, "--trials", "200", "--study", str(study)]
    proc = subprocess.Popen(
        [sys.executable, "-m", "puckboard", *args],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
    )  # fmt: skip
    seen: set[tuple[int, float]] = set()
    deadline = time.monotonic() + 180
    while finished(study) < 1:
        seen |= descendants(proc.pid)
        if proc.poll() is not None or time.monotonic() > deadline:
            proc.kill()
            pytest.fail(f"no finished trial: {proc.communicate()[1][-2000:]}")
        time.sleep(0.2)
    seen |= descendants(proc.pid)
    os.killpg(proc.pid, signal.SIGINT)
    try:
        _, err = proc.communicate(timeout=EXIT_WITHIN)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        pytest.fail(f"still running {EXIT_WITHIN} s after Ctrl-C")
    assert proc.returncode == 130
    assert err.strip().splitlines() == [
        f"puckboard tune: interrupted; finished trials are kept in {study}: run the same "
        "command again to resume"
    ]
    deadline = time.monotonic() + GONE_WITHIN
    while (left := [p for p in seen if alive(p)]) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not left, f"processes left behind: {sorted(p[0] for p in left)}"
    kept = finished(study)
    assert kept >= 1
    assert main([*TUNE, "--trials", str(kept + 1), "--study", str(study), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert (data["skipped"], data["ran"]) == (kept, 1)
