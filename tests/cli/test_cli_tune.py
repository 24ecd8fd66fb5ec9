"""``puckboard tune`` from the command line: the report, resuming, Ctrl-C and each mistake."""

from __future__ import annotations

import json
import sys

import pytest
from shared_sweeps import sweeps_share_episodes

from puckboard.cli import main

INNER = "layer.LineFollow.inner_factor"
#: The command of the issue's example, on episodes cut to a few seconds (every one fails,
#: quickly): the whole path of the command, in seconds.
SMALL = [
    "tune", "two-robot-pass", "--controller", "improved", "--param", f"{INNER}=0.1:0.9",
    "--trials", "3", "--seeds", "0:2", "--validate", "2:3", "--duration", "3",
    "--workers", "1", "--quiet",
]  # fmt: skip
#: The issue's command as it is written.
DONE_WHEN = [
    "tune", "two-robot-pass", "--controller", "improved", "--param", f"{INNER}=0.1:0.9",
    "--trials", "6", "--seeds", "0:4", "--validate", "4:8", "--json",
]  # fmt: skip


def one_error_line(capsys) -> str:
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith("puckboard tune: error: ")
    return lines[0]


def test_json_gives_the_best_parameters_with_design_and_validation_rates(capsys, tmp_path):
    study = tmp_path / "tune.journal"
    assert main([*SMALL, "--json", "--study", str(study)]) == 0
    data = json.loads(capsys.readouterr().out)
    assert (data["ran"], data["skipped"], len(data["trials"])) == (3, 0, 3)
    assert set(data["best"]["params"]) == {INNER}
    assert [(c["scene"], c["episodes"]) for c in data["design"]] == [("two-robot-pass", 2)]
    assert [(c["scene"], c["episodes"]) for c in data["validation"]] == [("two-robot-pass", 1)]
    assert data["use"].startswith(f"--controller improved --set {INNER}=")
    assert main([*SMALL, "--json", "--study", str(study)]) == 0
    again = json.loads(capsys.readouterr().out)
    assert (again["ran"], again["skipped"]) == (0, 3)
    assert again["trials"] == data["trials"]


@pytest.mark.slow
def test_the_documented_command_reports_and_then_resumes(capsys, tmp_path):
    """Whole episodes, run in this process (tests/support/shared_sweeps.py): the worker
    pool's part is tested with SMALL and by tests/tune/test_tune_interrupts.py."""
    study = ["--study", str(tmp_path / "tune.journal"), "--quiet"]
    with sweeps_share_episodes():
        assert main([*DONE_WHEN, *study]) == 0
        data = json.loads(capsys.readouterr().out)
        assert (data["ran"], len(data["trials"])) == (6, 6)
        assert INNER in data["best"]["params"]
        assert [c["episodes"] for c in data["design"]] == [4]
        assert [c["episodes"] for c in data["validation"]] == [4]
        assert main([*DONE_WHEN, *study]) == 0
    again = json.loads(capsys.readouterr().out)
    assert (again["ran"], again["skipped"], again["best"]) == (0, 6, data["best"])


def test_progress_names_the_trials_the_best_so_far_and_the_time_left(capsys):
    assert main([a for a in SMALL if a != "--quiet"]) == 0
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 4
    trials, validation = lines[:3], lines[3]
    assert (
        trials[-1].startswith("tune: trial 2 ") and "3/3 trials, best so far: trial " in trials[-1]
    )
    # validation, after the trials' "left ~0:00", has its own progress (1 seed, 1 cell)
    assert validation.startswith("tune validation: 1/1 episodes (100 %)")
    assert all("left ~" in line for line in lines)
    assert "validation (seeds 2:3)" in captured.out and "use it:" in captured.out


def test_ctrl_c_keeps_finished_trials_in_one_line_and_the_same_command_resumes(
    capsys, tmp_path, monkeypatch
):
    from puckboard.tune import objective

    study = tmp_path / "tune.journal"
    real = objective.run_cells
    calls = []

    def ctrl_c_in_the_second_trial(*args, **kwargs):
        calls.append(1)
        if len(calls) == 2:  # one round per trial: this is trial 1
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    monkeypatch.setattr("puckboard.tune.run.run_cells", ctrl_c_in_the_second_trial)
    args = [*SMALL, "--rounds", "1", "--study", str(study)]
    assert main(args) == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        f"puckboard tune: interrupted; finished trials are kept in {study}: run the same "
        "command again to resume"
    ]
    monkeypatch.setattr("puckboard.tune.run.run_cells", real)
    assert main([*args, "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert (data["skipped"], data["ran"]) == (1, 2)


@pytest.mark.parametrize(
    ("change", "words"),
    [
        (
            ["--param", "layer.LineFollow.inner=0.1:0.9"],
            "controller 'improved' has no such parameter; its factory's keywords: speed; its "
            "layers' attributes: layer.FrontObstacleLeftTurn.close_fraction,",
        ),
        (["--param", f"{INNER}=0.9:0.1"], "the range is reversed"),
        (["--param", f"{INNER}=0.5:0.5"], "the range is empty"),
        (["--validate", "1:3"], "--seeds and --validate share 1 seeds (first 1)"),
        (["--validate", "3:3"], "--validate '3:3' is empty"),
        (["--trials", "0"], "--trials must be at least 1"),
        (["--set", "robot.profile=epuck", "--profile", "epuck"], "not both"),
        (["--set", "noise.proximity=0,0.1"], "give one value"),
        (["--plot", "tune.gif"], "use a .png, .svg or .pdf"),
        (["--sampler-seed", "-1"], "--sampler-seed must be a whole number from 0 to 2**32 - 1"),
        (["--rounds", "100"], "--rounds 100 is more than the 2 design seeds of --seeds 0:2"),
        (
            ["--controller", "robust", "--param", "layer.LineSearch.ratio=0:1:int"],
            "layer.LineSearch.ratio is a real number (ships 0.5); an int range would round it",
        ),
        (
            ["--controller", "robust", "--param", "layer.LineFollow.recovery=0:1:int"],
            "is true or false, not a number; search it as a choice: "
            "--param layer.LineFollow.recovery=true,false",
        ),
    ],
)
def test_each_mistake_is_one_line_and_status_2(capsys, change, words):
    args = list(SMALL)
    for flag in change[::2]:
        if flag in args and flag not in ("--set", "--profile"):
            index = args.index(flag)
            del args[index : index + 2]
    assert main([*args, *change]) == 2
    assert words in one_error_line(capsys)


def test_a_study_file_of_another_command_is_one_line(capsys, tmp_path):
    study = ["--study", str(tmp_path / "tune.journal")]
    assert main([*SMALL, *study]) == 0
    capsys.readouterr()
    changed = [a if a != "0:2" else "0:1" for a in SMALL]
    assert main([*changed, *study]) == 2
    line = one_error_line(capsys)
    assert 'was made by another command (seeds: "0:2" there, "0:1" now)' in line


def test_a_study_file_cut_short_is_one_line_saying_what_it_holds(capsys, tmp_path):
    import dataclasses

    from sweep_helpers import DURATION, CountingExecutor

    from puckboard.scenario.scenefile import load_scene
    from puckboard.tune import TuneSpec, parse_param, run_tune

    study = tmp_path / "tune.journal"
    scene = dataclasses.replace(load_scene("two-robot-pass"), duration=DURATION)
    spec = TuneSpec((scene,), "improved", (parse_param(f"{INNER}=0.1:0.9"),), range(1), range(1, 2))
    run_tune(spec, 1, executor=CountingExecutor(), study_path=study)  # in this process: quick
    cut = tmp_path / "cut.journal"
    cut.write_bytes(study.read_bytes()[:400])  # a copy cut short
    assert main([*SMALL, "--study", str(cut)]) == 2
    line = one_error_line(capsys)
    assert f"--study '{cut}' is damaged: line " in line and "is cut short; the " in line
    assert "finished trial" in line and "copy those lines to a new file" in line


def test_a_true_false_setting_is_tuned_as_a_choice_and_the_line_to_use_sets_it(capsys):
    recovery = "layer.LineFollow.recovery"
    args = [
        "tune", "two-robot-pass", "--controller", "robust", "--param", f"{recovery}=false,true",
        "--trials", "2", "--seeds", "0:1", "--validate", "1:2", "--duration", "3",
        "--workers", "1", "--quiet", "--json",
        "--sampler-seed", str(2**32 - 1),  # the highest: trial 1's sampler wraps round
    ]  # fmt: skip
    assert main(args) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["params"] == [f"{recovery}=false,true"]
    assert data["trials"][0]["params"] == {recovery: True}  # robust ships recovery on
    assert data["trials"][1]["params"][recovery] in (True, False)
    best = data["best"]["params"][recovery]
    assert data["use"] == f"--controller robust --set {recovery}={str(best).lower()}"


def test_without_optuna_the_line_names_the_extra(capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "optuna", None)
    assert main(SMALL) == 2
    assert "pip install 'puckboard[tune]'" in one_error_line(capsys)
