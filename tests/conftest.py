"""Shared test helpers live in tests/support/, importable from every test folder.

Fixtures more than one folder uses are here; helpers are imported from tests/support by
their own module names, never from a ``conftest`` (every folder's conftest shares that
name, so two folders run together would collect one folder's helpers for the other's).

The suite runs on every core, with one worker more than there are cores (pytest-xdist,
``--dist worksteal`` in pyproject.toml): an idle worker takes tests queued for a busy one.
Each worker is a process of its own, so a result cached in one is computed again in
another: a result several tests use is kept with tests/support/session_cache.py (as
tests/support/episodes.py keeps episodes), computed by the first worker that asks and read
by the others.
"""

import dataclasses
import os
import shutil
import signal
import sys
import tempfile
import threading
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent / "support"))

import session_cache  # found through the path set above
from sweep_helpers import DURATION


@pytest.fixture(scope="session")
def short_scene():
    """The shipped line-follow scene, cut to a few seconds so sweeps and sensitivity
    analyses stay quick."""
    from puckboard.scenario.scenefile import load_scene

    return dataclasses.replace(load_scene("line-follow"), duration=DURATION)


def pytest_xdist_auto_num_workers(config: pytest.Config) -> int:
    """``-n auto``: one worker per CPU this process may run on, and one more. Some tests
    wait rather than compute (an emulated robot in real time, a browser drawing a page,
    a server's timeout): the extra worker computes while they wait. (pytest-xdist's own
    count is the physical cores', which is 1 on a machine of two hardware threads, and
    ignores a CPU affinity such as ``taskset``'s.)"""
    affinity = getattr(os, "sched_getaffinity", None)  # not on Windows or macOS
    cpus = len(affinity(0)) if affinity is not None else os.cpu_count() or 1
    return cpus + 1


def pytest_configure(config: pytest.Config) -> None:
    """The session's cache folder (tests/support/session_cache.py), made by the process
    that starts the workers, who inherit its name, and removed when the session ends.

    Ctrl-C as a terminal sends it: a shell that starts a job in the background (a CI
    runner, ``nohup``, ``cmd &``) starts it with SIGINT ignored, and every process it
    starts inherits that, so the commands the Ctrl-C tests interrupt would never see the
    signal. Python's own handler, installed here before any worker or command is started,
    is reset to the default in every program they run, as in a terminal's foreground job.
    """
    main = threading.current_thread() is threading.main_thread()  # handlers live there
    if main and signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    if hasattr(config, "workerinput"):  # a worker: the folder is its parent's
        return
    folder = tempfile.mkdtemp(prefix="puckboard-tests-")
    os.environ[session_cache.ENV] = folder
    config.add_cleanup(lambda: shutil.rmtree(folder, ignore_errors=True))
