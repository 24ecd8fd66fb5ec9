"""Grading a class: one grading of a folder holding the shipped controllers' factories and
a broken submission of every kind (tests/support/challenge_class.py), shared by the tests
here; the tests that change the output folder work on a copy of it."""

from __future__ import annotations

import csv
import itertools
import json
import re
import shutil
from pathlib import Path

import pytest
from challenge_class import SECRET, SUBMISSIONS, graded_class, rows_of

from puckboard.challenge import load_challenge
from puckboard.challenge.seeds import Secret
from puckboard.cli import main

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def graded():
    return graded_class()


def by_name(rows):
    return {row["name"]: row for row in rows if not row["baseline"]}


def test_every_broken_submission_gets_its_verdict_and_the_class_is_graded(graded):
    assert graded["status"] == "0", graded["stderr"]
    rows = by_name(rows_of(graded))
    assert {name: rows[name]["verdict"] for name in SUBMISSIONS} == {
        name: verdict for name, (_, verdict) in SUBMISSIONS.items()
    }
    # the reasons, in words a student acts on
    said = {name: rows[name]["verdict_text"] for name in SUBMISSIONS}
    assert "not_python.py is not valid Python" in said["not_python"]
    assert "No module named 'no_such_module_anywhere'" in said["no_import"]
    assert "defines no make_controller" in said["no_factory"]
    assert "returned int" in said["wrong_return"]
    assert "4 of 4 graded episodes raised an exception" in said["raises"]
    assert "did not finish its pre-flight check within 5 s" in said["sleeps"]
    assert "did not finish its pre-flight check within 5 s" in said["loops"]
    assert "sys.exit(3)" in said["sys_exit"]
    assert "exited with status 5" in said["os_exit"]
    assert "4 of 4 graded episodes ran out of memory" in said["hog"]
    assert rows["printer"]["remarks"] == ["printed to its output file"]
    assert rows["writer"]["remarks"] == ["wrote notes.txt"]
    # refused ones are listed, unranked, with no episode run
    for name in (
        "not_python",
        "no_import",
        "no_factory",
        "wrong_return",
        "sleeps",
        "loops",
        "sys_exit",
        "os_exit",
    ):
        assert rows[name]["rank"] is None and rows[name]["episodes"] == 0


def test_the_working_ones_rank_by_their_success_from_1(graded):
    rows = rows_of(graded)
    ranked = [r for r in rows if r["rank"] is not None]
    assert ranked[0]["rank"] == 1
    assert all(a["rank"] <= b["rank"] for a, b in itertools.pairwise(ranked))
    names = [r["name"] for r in ranked]
    assert names.index("robust_one") < names.index("improved_one") < names.index("stock_one")
    rates = [r["overall"]["success_rate"] for r in ranked if r["name"].endswith("_one")]
    assert rates == sorted(rates, reverse=True) and rates[0] == 1.0 > rates[-1]
    # the baseline is placed by the same rule and takes no rank
    baseline = next(r for r in rows if r["baseline"])
    assert baseline["name"] == "stock" and baseline["rank"] is None
    assert baseline["overall"] == by_name(rows)["stock_one"]["overall"]
    # every figure is the Wilson interval of its counts
    from puckboard.sweep.stats import wilson_interval

    for row in ranked:
        for rate in [row["overall"], *row["cells"].values()]:
            assert (rate["ci95_low"], rate["ci95_high"]) == pytest.approx(
                wilson_interval(rate["successes"], rate["episodes"])
            )


def test_no_graded_seed_is_in_any_output_before_reveal(graded):
    challenge = load_challenge(graded["challenge"])
    seeds = Secret(SECRET, challenge.name).graded_seeds(challenge)
    every = [s for cell in seeds.values() for s in cell]
    texts = [graded["json"], graded["stderr"]]
    for path in Path(graded["out"]).rglob("*"):
        if path.is_file():
            texts.append(path.read_text(encoding="utf-8", errors="replace"))
    assert len(texts) > 20  # the folder's files were read, replays and versions included
    for text in texts:
        for seed in every:
            assert not re.search(rf"(?<![\d.]){seed}(?![\d])", text), seed


def test_results_csv_holds_the_leaderboard_in_rank_order(graded):
    with (Path(graded["out"]) / "results.csv").open(newline="", encoding="utf-8") as f:
        table = list(csv.DictReader(f))
    rows = rows_of(graded)
    assert [r["name"] for r in table] == [r["name"] for r in rows]
    assert {r["view"] for r in table} == {"latest"}
    robust = next(r for r in table if r["name"] == "robust_one")
    assert robust["rank"] == "1" and float(robust["success_rate"]) == 1.0
    assert set(robust) >= {
        "cell.pass.success_rate",
        "cell.bend.ci95_low",
        "graded_at",
        "replay_success",
    }


def test_each_graded_entry_links_its_replays_and_they_exist(graded):
    rows = rows_of(graded)
    robust = by_name(rows)["robust_one"]
    assert "success" in robust["replays"] and "worst" not in robust["replays"]  # it never failed
    stock = by_name(rows)["stock_one"]
    assert "worst" in stock["replays"]
    for row in rows:
        for link in row["replays"].values():
            page = Path(graded["out"]) / link
            assert page.is_file() and "replay-data" in page.read_text(encoding="utf-8")


@pytest.fixture
def copy(graded, tmp_path):
    """The graded class's folder, copied: a test may change it."""
    folder = tmp_path / "copy"
    shutil.copytree(graded["folder"], folder)
    return folder


def grade(folder: Path, *extra: str) -> tuple[int, dict, str]:
    import contextlib
    import io

    out, err = io.StringIO(), io.StringIO()
    argv = [
        "challenge", "grade", str(folder / "test-pass.toml"), str(folder / "class"),
        "--secret-file", str(folder / "secret.txt"), "--out", str(folder / "results"),
        "--workers", "2", "--json", "--quiet", *extra,
    ]  # fmt: skip
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(argv)
    return status, (json.loads(out.getvalue()) if out.getvalue() else {}), err.getvalue()


def test_a_late_hand_in_grades_only_what_is_new_and_the_final_view_stays(copy):
    status, first, _ = grade(copy, "--final")  # the deadline: nothing new to run
    assert status == 0 and first["ran"] == 0 and first["checked"] == 0 and first["view"] == "final"
    better = SUBMISSIONS["robust_one"][0] + "# handed in late\n"
    (copy / "class" / "stock_one.py").write_text(better)
    status, again, _ = grade(copy)
    assert status == 0
    assert again["new"] == [next(r["version"] for r in again["latest"] if r["name"] == "stock_one")]
    assert again["checked"] == 1 and again["ran"] == 4  # its 2 cells x 2 episodes, nothing else
    final = {r["name"]: r for r in again["rows"]}
    latest = {r["name"]: r for r in again["latest"]}
    assert final["stock_one"]["overall"]["success_rate"] == 0.0  # the final ranking keeps it
    assert latest["stock_one"]["overall"]["success_rate"] == 1.0
    assert final["stock_one"]["version"] != latest["stock_one"]["version"]
    history = json.loads((copy / "results" / "history.json").read_text())
    assert len(history["versions"]["stock_one"]) == 2  # both kept, each with its copy
    page = (copy / "results" / "leaderboard.html").read_text()
    assert 'id="latest"' in page and "Final ranking" in page


def test_reveal_shows_the_seeds_everywhere(copy, graded):
    status, shown, _ = grade(copy, "--reveal")
    assert status == 0 and shown["ran"] == 0
    challenge = load_challenge(graded["challenge"])
    seeds = Secret(SECRET, challenge.name).graded_seeds(challenge)
    assert shown["seeds"] == {cell: list(s) for cell, s in seeds.items()}
    page = (copy / "results" / "leaderboard.html").read_text()
    assert all(str(s) in page for cell in seeds.values() for s in cell)
    with (copy / "results" / "graded-episodes.csv").open(newline="") as f:
        episodes = list(csv.DictReader(f))
    assert {int(r["seed"]) for r in episodes} == {s for cell in seeds.values() for s in cell}
    assert shown["view"] == "final"  # revealing freezes the final ranking


@pytest.mark.parametrize(
    ("change", "said"),
    [
        ("secret", "was graded with another secret"),
        ("challenge", "holds the results of another challenge (episodes 2 there, 3 here)"),
        ("twins", "two submissions have the same name"),
    ],
)
def test_an_unusable_grading_is_refused_in_one_line_and_loses_nothing(copy, change, said):
    before = (copy / "results" / "episodes.csv").read_bytes()
    if change == "secret":
        (copy / "secret.txt").write_text("another secret phrase")
    elif change == "challenge":
        path = copy / "test-pass.toml"
        path.write_text(path.read_text().replace("episodes = 2", "episodes = 3"))
    else:
        (copy / "class" / "Printer.py").write_text("X = 1\n")
        if len(list((copy / "class").glob("[Pp]rinter.py"))) < 2:
            pytest.skip("this file system does not tell names apart by case")
    status, _, err = grade(copy)
    assert status == 2
    assert said in err and len(err.strip().splitlines()) == 1, err
    assert (copy / "results" / "episodes.csv").read_bytes() == before
