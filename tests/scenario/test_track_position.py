"""A point followed along a track finds, to the bit, what testing every segment finds."""

from __future__ import annotations

import math

import numpy as np
import pytest

from puckboard.scenario.track_position import NearestSegment, TrackProjector


def full_answer(track: TrackProjector, x: float, y: float, radius: float):
    """What numpy's test of every segment says: (segment, t, squared distance) of the
    nearest when within ``radius``, else None."""
    t, d2 = track._squared(np.array([[x, y]]))
    best = int(np.argmin(d2[0]))
    if np.sqrt(d2[0, best]) > radius:
        return None
    return best, float(t[0, best]), float(d2[0, best])


def tracks(rng: np.random.Generator):
    """Tracks that make the search work: a stadium of short segments and long
    straights, a self-crossing figure of eight, a jagged open line with a segment of
    zero length, and a line drawn twice (every nearest segment a tie)."""
    a = np.linspace(0, 2 * np.pi, 160, endpoint=False)
    stadium = np.column_stack([0.4 * np.sign(np.cos(a)) + 0.25 * np.cos(a), 0.25 * np.sin(a)])
    eight = np.column_stack([0.5 * np.sin(a), 0.3 * np.sin(2 * a)])
    jagged = np.cumsum(rng.normal(0.0, 0.03, size=(60, 2)), axis=0)
    jagged[20] = jagged[19]
    line = np.column_stack([np.linspace(-0.5, 0.5, 30), np.zeros(30)])
    twice = np.vstack([line, line[::-1]])
    for points, closed in ((stadium, True), (eight, True), (jagged, False), (twice, False)):
        ends = np.roll(points, -1, axis=0) if closed else points[1:]
        starts = points if closed else points[:-1]
        yield TrackProjector(np.stack([starts, ends], axis=1), closed)


@pytest.mark.parametrize("seed", [0, 1])
def test_following_a_point_finds_what_testing_every_segment_finds(seed):
    rng = np.random.default_rng(seed)
    for track in tracks(rng):
        for radius in (0.0195, 0.10, math.inf):
            follower = NearestSegment(track)
            x, y = track.segments[0][0], track.segments[0][1]
            for step in range(1500):
                if step % 300 == 299:  # a jump: the bounds must not hold it back
                    x, y = rng.uniform(-0.7, 0.7, size=2).tolist()
                else:  # a walk of a few millimetres a step, as a robot drives
                    dx, dy = rng.normal(0.0, 0.004, size=2).tolist()
                    x, y = x + dx, y + dy
                assert follower.query(x, y, radius) == full_answer(track, x, y, radius)


def test_a_point_on_a_segment_end_gets_the_lower_index_as_argmin_does():
    line = np.array([[[0.0, 0.0], [0.1, 0.0]], [[0.1, 0.0], [0.2, 0.0]]])
    track = TrackProjector(line, closed=False)
    follower = NearestSegment(track)
    assert follower.query(0.1, 0.05, 1.0) == full_answer(track, 0.1, 0.05, 1.0)
    assert follower.query(0.1, 0.05, 1.0)[0] == 0
