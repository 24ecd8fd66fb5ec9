"""The time left a sweep's progress line says: the pace since the first result."""

from __future__ import annotations

import io

from puckboard.sweep.progress import PlainProgress


class Clock:
    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


def test_early_estimates_leave_out_the_start_up_and_the_first_batches_in_flight():
    """80 episodes on two workers in batches of 8, 4 s an episode, the first results
    after 48 s (start-up and a batch each, side by side): the sweep ends at 164 s. At
    60 s the time to the first result, counted in as once, said 240 s were left."""
    clock = Clock()
    progress = PlainProgress(io.StringIO(), every=1e9, clock=clock)
    progress.start(80)
    assert progress.eta() is None
    for t in (48.0, 48.5):  # each worker's first batch
        clock.t = t
        progress.advance(8)
    clock.t = 60.0
    left = progress.eta()
    assert left is not None and abs(left - (164 - 60)) / (164 - 60) < 0.1
    clock.t = 120.0
    for _ in range(6):  # rounds at 80 and 112 s
        progress.advance(8)
    assert progress.eta() == (120 - 48) / (64 - 8) * 16  # the pace since the first result
    progress.advance(16)
    assert progress.eta() == 0.0


def test_a_resumed_sweep_counts_none_of_the_skipped_episodes_towards_the_pace():
    clock = Clock()
    out = io.StringIO()
    progress = PlainProgress(out, every=1e9, clock=clock)
    progress.start(20, done=10)
    assert out.getvalue() == "sweep: 10/20 episodes already in the output file\n"
    clock.t = 5.0
    progress.advance(2)
    assert progress.eta() is None  # one result: no pace yet
    clock.t = 9.0
    progress.advance(2)
    assert progress.eta() == 4.0 / 2 * 6
