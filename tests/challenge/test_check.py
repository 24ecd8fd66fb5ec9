"""``puckboard challenge check``: the grader's own checks before handing in, one verdict."""

from __future__ import annotations

import json

import pytest
from challenge_class import SUBMISSIONS, write_class

from puckboard.cli import main


@pytest.fixture(scope="module")
def challenge(tmp_path_factory):
    folder = tmp_path_factory.mktemp("check")
    path, submissions = write_class(folder)
    return path, submissions


def check(capsys, file, challenge, *extra):
    status = main(
        ["challenge", "check", str(file), "--challenge", str(challenge), "--quiet", *extra]
    )
    captured = capsys.readouterr()
    return status, captured.out, captured.err


@pytest.mark.parametrize(
    ("name", "verdict"),
    [
        ("not_python", "would not be graded: not_python.py is not valid Python: invalid syntax"),
        ("no_factory", "would not be graded: no_factory.py defines no make_controller(**params)"),
        ("wrong_return", "would not be graded: make_controller() returned int"),
        ("sys_exit", "would not be graded: make_controller() ended the process (sys.exit(3))"),
        ("raises", "would be graded, but fix this first: a layer raised in its first ticks: "
                   "RuntimeError: my layer broke"),
    ],
)  # fmt: skip
def test_check_names_the_problem(capsys, challenge, name, verdict):
    path, submissions = challenge
    status, out, _ = check(capsys, submissions / f"{name}.py", path)
    assert status == 1
    assert out.strip().splitlines()[-1].startswith(verdict), out


def test_a_sleeping_layer_is_stopped_at_the_checks_limit(capsys, challenge):
    path, submissions = challenge
    status, out, _ = check(capsys, submissions / "sleeps.py", path)
    assert status == 1
    assert out.strip().splitlines()[-1] == (
        "would not be graded: did not finish its pre-flight check within 5 s: importing it, "
        "building its controller or its first ticks sleep, block or never return"
    )


def test_a_working_file_would_be_graded_and_says_what_it_ran(capsys, challenge):
    path, submissions = challenge
    status, out, _ = check(capsys, submissions / "printer.py", path, "--json")
    assert status == 0
    report = json.loads(out)
    assert report["verdict"] == "would be graded" and report["ok"]
    assert report["preflight"]["layers"] == [
        "FrontBraitenbergAvoid",
        "LineFollow",
        "SideWallKeep",
        "Cruise",
    ]
    ticks = report["preflight"]["ticks"]
    assert ticks["ticks"] == 40 and ticks["period_s"] == pytest.approx(0.05)
    assert [(p["cell"], p["seed"]) for p in report["practice"]] == [("line", 0)]
    assert report["printed_lines"] >= 1  # what it printed went to a file, not this report


def test_a_missing_file_or_challenge_is_one_line(capsys, challenge, tmp_path):
    path, _ = challenge
    status, _, err = check(capsys, tmp_path / "nowhere.py", path)
    assert (
        status == 2
        and err.strip()
        == f"puckboard challenge: error: no file {str(tmp_path / 'nowhere.py')!r} to check"
    )
    status, _, err = check(capsys, tmp_path / "nowhere.py", "no-such-challenge")
    assert status == 2 and "no challenge 'no-such-challenge'" in err and len(err.splitlines()) == 1


def test_list_names_the_shipped_challenges_one_a_line(capsys):
    assert main(["challenge", "list"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines and all(line.split()[0] in ("pass",) for line in lines)
    assert main(["challenge", "show", "pass"]) == 0
    assert 'name = "pass"' in capsys.readouterr().out
    assert SUBMISSIONS  # the class the other tests grade
