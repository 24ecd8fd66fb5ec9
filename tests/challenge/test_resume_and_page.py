"""A grading killed with SIGKILL half-way resumes to the leaderboard an uninterrupted one
gives; the page opens from disk in a real headless browser with ranks from 1."""

from __future__ import annotations

import csv
import io
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from challenge_class import SECRET, graded_class, rows_of, write_class

pytestmark = pytest.mark.slow

#: What two gradings of one class may differ in: when they ran, and what was timed.
WHEN = ("first_seen", "graded_at")


def leaderboard(out: Path) -> list[dict[str, str]]:
    """``results.csv`` without the columns that say when, and with times measured in a
    remark masked."""
    import re

    with (out / "results.csv").open(newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    for row in rows:
        for column in WHEN:
            row.pop(column)
        row["remarks"] = re.sub(r"\d+ ms", "N ms", row["remarks"])
    return rows


#: The part of the class the kill test grades: enough to be half-way through at the kill.
KILLED_CLASS = ("robust_one", "stock_one", "raises", "not_python")


@pytest.mark.skipif(os.name != "posix", reason="kill -9 is SIGKILL")
def test_ctrl_c_then_kill_9_and_the_same_command_gives_the_same_leaderboard(tmp_path):
    """Part of the class, stopped by Ctrl-C and then by SIGKILL once a few episodes more
    are on disk each time, then graded again by the same command: every entry's row is
    what the whole class's uninterrupted grading gave it, in the same order."""
    reference = graded_class()
    challenge, submissions = write_class(tmp_path)
    for path in submissions.glob("*.py"):
        if path.stem not in KILLED_CLASS:
            path.unlink()
    (tmp_path / "secret.txt").write_text(SECRET)
    out = tmp_path / "results"
    command = [
        sys.executable, "-m", "puckboard", "challenge", "grade", str(challenge),
        str(submissions), "--secret-file", str(tmp_path / "secret.txt"), "--out", str(out),
        "--workers", "2", "--quiet",
    ]  # fmt: skip
    episodes = out / "episodes.csv"

    def rows() -> int:
        return episodes.read_bytes().count(b"\n") - 1 if episodes.exists() else 0

    def start_and_wait_for(more: int) -> subprocess.Popen[str]:
        before = rows()
        process = subprocess.Popen(
            command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
        )
        deadline = time.monotonic() + 300
        while rows() < before + more:
            assert process.poll() is None, process.communicate()
            assert time.monotonic() < deadline, f"no {more} episodes graded in 300 s"
            time.sleep(0.05)
        return process

    # Ctrl-C: the episodes that finished are kept, the page says who is incomplete
    first = start_and_wait_for(3)
    first.send_signal(signal.SIGINT)
    _, err = first.communicate(timeout=60)
    assert first.returncode == 130, err
    assert (
        err.splitlines()[-1].startswith("puckboard challenge: interrupted; ")
        and "Traceback" not in err
    )
    kept = rows()
    assert "incomplete" in (out / "results.csv").read_text()
    # kill -9: nothing said, nothing lost but the episodes running
    second = start_and_wait_for(3)
    assert rows() > kept
    second.send_signal(signal.SIGKILL)
    second.communicate()
    again = subprocess.run(command, capture_output=True, text=True, timeout=600)
    assert again.returncode == 0, again.stderr
    assert " 0 already graded" not in again.stdout  # it resumed
    resumed = leaderboard(out)
    whole = [
        r for r in leaderboard(Path(reference["out"])) if r["name"] in (*KILLED_CLASS, "stock")
    ]
    unranked = [{k: v for k, v in r.items() if k != "rank"} for r in resumed]
    assert unranked == [{k: v for k, v in r.items() if k != "rank"} for r in whole]
    assert resumed[0]["rank"] == "1"


def test_the_page_opens_from_disk_in_a_browser_with_ranks_from_1():
    from browser import Browser, chromium

    binary = chromium()
    if binary is None:
        pytest.skip("no Chromium found; install Debian's 'chromium' package, as .ci/run does")
    graded = graded_class()
    page = Path(graded["out"]) / "leaderboard.html"
    expected = [r for r in rows_of(graded)]
    with Browser(binary) as browser:
        browser.open(page.as_uri())
        browser.wait_for(
            "document.readyState === 'complete' && !!document.querySelector('#leaderboard')"
        )
        shown = browser.evaluate(
            "[...document.querySelectorAll('#leaderboard tbody tr')].map(r => "
            "[r.querySelector('.rank').textContent, r.querySelector('.entry').textContent, "
            "r.classList.contains('baseline')])"
        )
        assert [s[1] for s in shown] == [r["name"] for r in expected]
        ranks = [int(s[0]) for s in shown if s[0]]
        assert ranks[0] == 1 and ranks == sorted(ranks)
        assert [s[2] for s in shown] == [r["baseline"] for r in expected]
        # nothing was fetched: the page is whole on disk
        assert browser.evaluate("performance.getEntriesByType('resource').length") == 0
        # a replay link opens the offline player
        link = browser.evaluate("document.querySelector('a.replay').getAttribute('href')")
        browser.open((page.parent / link).as_uri())
        browser.wait_for("window.state && state.player && state.readyAt")
        assert browser.evaluate("document.title").startswith("puckboard — replay")


def test_the_terminal_table_and_json_agree(tmp_path):
    """What the command prints without --json, on the same folder: nothing runs again."""
    import contextlib
    import shutil

    from puckboard.cli import main

    graded = graded_class()
    folder = tmp_path / "copy"
    shutil.copytree(graded["folder"], folder)
    out = io.StringIO()
    argv = [
        "challenge", "grade", graded["challenge"].replace(graded["folder"], str(folder)),
        str(folder / "class"), "--secret-file", str(folder / "secret.txt"), "--out",
        str(folder / "results"), "--workers", "1", "--quiet",
    ]  # fmt: skip
    with contextlib.redirect_stdout(out):
        assert main(argv) == 0
    text = out.getvalue()
    assert "0 checked, 0 episodes run, 32 already graded" in text  # 7 entries and stock, x4
    lines = {line.split()[1]: line for line in text.splitlines() if line[:5].strip().isdigit()}
    assert lines["robust_one"].split()[0] == "1"
    assert "sleeps: timeout: not graded: did not finish its pre-flight check within 5 s" in text
    assert "stock (baseline)" in text
