"""Pieces the sweep tests share: the short episodes' length and an executor that counts
the episodes it runs (a module of its own, so that tests import it by a name no other
folder's conftest shares)."""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
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
