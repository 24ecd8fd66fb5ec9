"""Shared pieces for the sweep tests: a short scene and executors that count episodes."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterator, Sequence
from typing import Any

import pytest

from puckboard.sweep.executors import InlineExecutor

#: Simulated seconds per test episode: long enough for the judge to see the robots move.
DURATION = 3.0


@pytest.fixture(scope="session")
def short_scene():
    """The shipped line-follow scene, cut to a few seconds so sweeps stay quick."""
    from puckboard.scenario.scenefile import load_scene

    return dataclasses.replace(load_scene("line-follow"), duration=DURATION)


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
