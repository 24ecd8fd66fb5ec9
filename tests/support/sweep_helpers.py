"""Pieces the sweep tests share: the short episodes' length, an executor that counts
the episodes it runs, a stop flag that says when its batch has run an episode, and the
worker processes a pool created (a module of its own, so that tests import it by a name
no other folder's conftest shares).

Tests that need another process to have got somewhere wait for it to say so, with a
generous timeout, never for a fixed time: on a loaded machine any fixed time is too
short.
"""

from __future__ import annotations

import multiprocessing
import time
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

from puckboard.sweep.executors import InlineExecutor

#: Simulated seconds per test episode: long enough for the judge to see the robots move.
DURATION = 3.0


class CountingExecutor(InlineExecutor):
    """In-process executor that records every episode it was asked to run."""

    def __init__(self, interrupt_after: int | None = None) -> None:
        self.ran: list[Any] = []
        self.interrupt_after = interrupt_after

    def run(self, fn: Callable[..., Any], tasks: Sequence[tuple[Any, ...]]) -> Iterator[Any]:
        for done, task in enumerate(tasks):
            if self.interrupt_after is not None and done >= self.interrupt_after:
                raise KeyboardInterrupt
            self.ran.extend(task[2])
            yield fn(*task)


#: How long a test waits for another process before it fails: far longer than any wait
#: needs, even on a machine whose every core is busy with other work.
PATIENCE_S = 120.0


def wait_until(condition: Callable[[], bool], what: str, timeout: float = PATIENCE_S) -> None:
    """Return once ``condition()`` holds; fail, naming ``what``, after ``timeout`` s."""
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, f"waited {timeout:.0f} s for {what}"
        time.sleep(0.01)


class StopAfterFirstEpisode:
    """A batch's stop flag (wrapping the executor's own, ``flag``) that, asked before the
    batch's second episode, touches ``marker`` and waits for ``flag`` to say stop.

    The batch has then finished exactly one episode whatever the machine's load, so a
    test can stop a pool while its batches are surely running and know what they ran.
    Picklable: it travels to the worker with its batch.
    """

    def __init__(self, flag: Callable[[], bool], marker: Path) -> None:
        self.flag = flag
        self.marker = marker
        self.asked = 0

    def __call__(self) -> bool:
        self.asked += 1
        if self.asked == 2:
            self.marker.touch()
            wait_until(self.flag, "the pool's stop")
        return self.flag()


def new_children(before: set[Any]) -> list[Any]:
    """The multiprocessing children of this process that were not in ``before`` (an
    earlier ``set(multiprocessing.active_children())``): the workers a pool created."""
    return [p for p in multiprocessing.active_children() if p not in before]
