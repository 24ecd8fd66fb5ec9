"""Ctrl-C and SIGTERM on a real ``puckboard sweep`` and ``puckboard bench --suite sweep``.

Each test starts the command in a process group of its own and signals it the way a
terminal does (SIGINT to the whole group: parent and workers alike) or the way ``kill``
does (SIGTERM to the parent alone), at a moment recognised from outside: worker processes
exist, the first row is in ``--out``, the Dask cluster's workers exist. The command must
then end with its exit status and one line on stderr — no traceback — keep the rows that
finished, and leave no process behind.

``EXIT_WITHIN`` is a hang check (the fault it guards against hung for over ten minutes),
not a timing: a stopped sweep waits at most ``STOP_GRACE`` (2 s) for running episodes.
"""

from __future__ import annotations

import contextlib
import csv
import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from process_tree import alive, command_line, descendants, require_process_tree

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(
        os.name != "posix", reason="signals a process group, as a POSIX terminal's Ctrl-C does"
    ),
]

EXIT_WITHIN = 15.0
#: multiprocessing's resource tracker ends on its own just after the command.
GONE_WITHIN = 5.0

#: Many short episodes: the sweep is still running when the signal comes.
SWEEP = [
    "sweep", "line-follow", "--controller", "stock", "--seeds", "0:2000", "--duration", "20",
    "--workers", "2", "--quiet",
]  # fmt: skip


class Command:
    """A ``puckboard`` command in its own process group, watched from outside."""

    def __init__(self, *args: str) -> None:
        require_process_tree()
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "puckboard", *args],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            start_new_session=True,
        )
        self.seen: set[tuple[int, float]] = set()
        #: each seen process's latest command line, read while it lived
        self.command_lines: dict[tuple[int, float], str] = {}
        self.exit_s = float("nan")

    def watch(self) -> set[tuple[int, float]]:
        now = descendants(self.proc.pid)
        for process in now:  # read again: a child shows its parent's line until it execs
            if line := command_line(process[0]):
                self.command_lines[process] = line
        self.seen |= now
        return now

    def wait_for(self, what: str, condition: Callable[[], bool], timeout: float = 120) -> None:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            self.watch()
            if condition():
                return
            if self.proc.poll() is not None:
                pytest.fail(f"ended before {what}: {self.proc.communicate()[1][-2000:]}")
            time.sleep(0.05)
        self.kill()
        pytest.fail(f"no {what} within {timeout} s")

    def signal(self, signum: int, *, group: bool = True) -> None:
        self.watch()
        self._t0 = time.monotonic()
        if group:
            os.killpg(self.proc.pid, signum)
        else:
            os.kill(self.proc.pid, signum)

    def finish(self, *, spawns: bool = True) -> tuple[int, list[str]]:
        """Exit status and stderr lines, once it has exited and its processes are gone
        (``spawns``: it was seen to start worker processes, else the check would prove
        nothing; multiprocessing's resource tracker, which a library may start on its
        own, is not a worker)."""
        try:
            self.proc.wait(timeout=EXIT_WITHIN)
        except subprocess.TimeoutExpired:
            self.kill()
            pytest.fail(f"still running {EXIT_WITHIN} s after the signal")
        self.exit_s = time.monotonic() - self._t0
        _, err = self.proc.communicate(timeout=GONE_WITHIN)
        deadline = time.monotonic() + GONE_WITHIN
        while (left := [p for p in self.seen if alive(p)]) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert not left, f"processes left behind: {sorted(p[0] for p in left)}"
        workers = {p: line for p, line in self.command_lines.items() if _is_worker(line)}
        assert bool(workers) == spawns, self.command_lines
        assert "Traceback" not in err, err
        return self.proc.returncode, err.splitlines()

    def kill(self) -> None:
        for pid, _ in self.watch():
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)
        self.proc.kill()
        self.proc.communicate()


def rows_in(path: Path) -> int:
    if not path.exists():
        return 0
    with path.open(newline="", encoding="utf-8") as handle:
        return sum(1 for _ in csv.DictReader(handle))


def kept(line: str) -> int:
    """The episode count of ``puckboard sweep: interrupted; N episodes of this run kept``."""
    return int(line.split("; ")[1].split()[0])


def _is_worker(line: str) -> bool:
    """Whether a command line is a spawned worker's (local workers are always spawned),
    not a helper a library starts on its own, such as multiprocessing's resource tracker
    or a one-off system query."""
    return "spawn_main" in line and "resource_tracker" not in line


def _workers_started(command: Command) -> bool:
    """Whether a worker process exists (spawned, so most likely still importing), not
    only multiprocessing's resource tracker."""
    return any("spawn_main" in command_line(pid) for pid, _ in command.watch())


def test_ctrl_c_while_local_workers_start(tmp_path):
    command = Command(*SWEEP, "--out", str(tmp_path / "runs.csv"))
    command.wait_for("worker processes", lambda: _workers_started(command))
    command.signal(signal.SIGINT)
    status, err = command.finish()
    assert status == 130
    assert len(err) == 1 and err[0].startswith("puckboard sweep: interrupted"), err


@pytest.mark.parametrize(("signum", "status", "word"), [
    (signal.SIGINT, 130, "interrupted"),
    (signal.SIGTERM, 143, "terminated"),
])  # fmt: skip
def test_a_stopped_sweep_keeps_its_finished_rows(tmp_path, signum, status, word):
    out = tmp_path / "runs.csv"
    command = Command(*SWEEP, "--out", str(out))
    command.wait_for("a finished row", lambda: rows_in(out) > 0)
    # Ctrl-C reaches every process of the group; SIGTERM (kill PID) only the command
    command.signal(signum, group=signum == signal.SIGINT)
    code, err = command.finish()
    assert code == status
    assert len(err) == 1 and err[0].startswith(f"puckboard sweep: {word}; "), err
    assert kept(err[0]) == rows_in(out) > 0
    assert rows_in(out) < 2000  # it did stop


def test_a_stopped_sensitivity_analysis_keeps_its_rows_and_resumes(tmp_path):
    """The analysis runs on the sweep's machinery: Ctrl-C keeps what ran, the same
    command takes up from there."""
    out = tmp_path / "runs.csv"
    analysis = [
        "sensitivity", "line-follow", "--controller", "stock", "--profile", "epuck",
        "--seeds", "0:100", "--duration", "20", "--workers", "2", "--quiet", "--out", str(out),
    ]  # fmt: skip
    command = Command(*analysis)
    command.wait_for("a finished row", lambda: rows_in(out) > 0)
    command.signal(signal.SIGINT)
    code, err = command.finish()
    assert code == 130
    assert len(err) == 1 and err[0].startswith("puckboard sensitivity: interrupted; "), err
    assert kept(err[0]) == rows_in(out) > 0
    before = rows_in(out)
    again = Command(*analysis)
    again.wait_for("a row more", lambda: rows_in(out) > before)
    again.signal(signal.SIGINT)
    code, err = again.finish()
    assert code == 130 and kept(err[0]) == rows_in(out) - before


SLOW_CONTROLLER = """
import time
from pathlib import Path
from puckboard.behaviours import Controller, Cruise

class Slow(Cruise):
    def command(self, frame):
        Path({marker!r}).touch()  # an episode is running
        time.sleep(0.05)  # 400 steps: 20 s, far longer than the stop's 2 s of grace
        return super().command(frame)

def make_controller(**params):
    return Controller([Slow()], name="slow")
"""


def test_a_second_ctrl_c_stops_without_waiting(tmp_path):
    """The first Ctrl-C waits (up to 2 s) for running episodes; the second does not."""
    marker = tmp_path / "running"
    slow = tmp_path / "slow.py"
    slow.write_text(SLOW_CONTROLLER.format(marker=str(marker)))
    command = Command(
        "-v", "sweep", "line-follow", "--controller", f"{slow.as_posix()}:make_controller",
        "--seeds", "0:4", "--duration", "20", "--workers", "2", "--quiet",
    )  # fmt: skip
    command.wait_for("a running episode", marker.exists)
    command.signal(signal.SIGINT)
    time.sleep(0.3)
    os.killpg(command.proc.pid, signal.SIGINT)
    code, err = command.finish()
    assert code == 130
    assert any("interrupted again: not waiting for running episodes" in line for line in err)
    assert err[-1] == (
        "puckboard sweep: interrupted; 0 episodes ran and none is kept: add --out FILE (.csv "
        "or .parquet) to keep finished episodes; the same command then resumes from it"
    ), err


@pytest.fixture(scope="module")
def dask_cluster():
    pytest.importorskip("dask.distributed")
    from puckboard.sweep import DaskExecutor

    with DaskExecutor(local_workers=2) as executor:
        yield executor


def test_ctrl_c_on_a_dask_cluster_frees_its_workers(tmp_path, dask_cluster):
    out = tmp_path / "runs.csv"
    address = dask_cluster.client.scheduler.address
    command = Command(*SWEEP[:-3], "--scheduler", address, "--quiet", "--out", str(out))
    command.wait_for("a finished row", lambda: rows_in(out) > 0)
    command.signal(signal.SIGINT)  # the cluster is not in the command's group
    code, err = command.finish(spawns=False)
    assert code == 130
    assert len(err) == 1 and err[0].startswith("puckboard sweep: interrupted; "), err
    assert kept(err[0]) == rows_in(out) > 0
    # the batches saw the stop flag: the workers are free again, not busy with our sweep
    deadline = time.monotonic() + EXIT_WITHIN
    while any(dask_cluster.client.processing().values()) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not any(dask_cluster.client.processing().values())


BENCH = ["bench", "--suite", "sweep", "--steps", "10", "--json"]


def test_ctrl_c_on_the_sweep_benchmark_while_local_workers_start():
    command = Command(*BENCH)
    command.wait_for("worker processes", lambda: _workers_started(command))
    command.signal(signal.SIGINT)
    status, err = command.finish()
    assert status == 130
    assert err == ["puckboard bench: interrupted"]


def _cluster_workers(command: Command) -> bool:
    """Whether a child of the command has children: the local Dask cluster's workers."""
    return any(descendants(pid) for pid, _ in command.watch())


@pytest.mark.parametrize(("signum", "status", "line"), [
    (signal.SIGINT, 130, "puckboard bench: interrupted"),
    (signal.SIGTERM, 143, "puckboard bench: terminated"),
])  # fmt: skip
def test_stopping_the_sweep_benchmark_on_its_dask_cluster(signum, status, line):
    command = Command(*BENCH)
    command.wait_for("the Dask cluster's workers", lambda: _cluster_workers(command))
    command.signal(signum, group=signum == signal.SIGINT)
    code, err = command.finish()
    assert code == status
    assert err == [line]
