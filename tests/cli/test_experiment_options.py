"""The options every experiment command shares (cli/experiment_options): how a stopped
run ends, said the same way by sweep and sensitivity."""

from __future__ import annotations

import argparse
from types import SimpleNamespace

import pytest

from puckboard.cli.experiment_options import exit_status


def _stopped(ran: int) -> SimpleNamespace:
    return SimpleNamespace(interrupted=True, terminated=False, ran=ran, errors=[])


@pytest.mark.parametrize("command", ["sweep", "sensitivity"])
def test_an_interrupted_run_without_out_says_nothing_is_kept_and_how_to_keep_it(capsys, command):
    args = argparse.Namespace(out=None)
    assert exit_status(args, _stopped(8), stored=False, command=command) == 130
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line == (
        f"puckboard {command}: interrupted; 8 episodes ran and none is kept: add --out FILE "
        "(.csv or .parquet) to keep finished episodes; the same command then resumes from it"
    )
    assert " kept in " not in line


def test_an_interrupted_run_with_out_names_the_file_that_keeps_them(capsys, tmp_path):
    out = tmp_path / "runs.csv"
    args = argparse.Namespace(out=out)
    assert exit_status(args, _stopped(8), stored=True, command="sweep") == 130
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line == (
        f"puckboard sweep: interrupted; 8 episodes of this run kept in {out}; run the same "
        "command again to resume"
    )
