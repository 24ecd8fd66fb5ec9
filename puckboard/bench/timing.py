"""The one way every benchmark suite times code.

A figure is the median over ``repeats`` of the mean time per call of ``calls`` calls,
after a short warm-up: the mean inside a repeat smooths the timer's resolution, and the
median across repeats discards a repeat the machine's load disturbed. Times are seconds
here; suites convert to the unit they report (µs, ms) in one place, their key's suffix.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable, Iterable
from typing import Any

__all__ = ["REPEATS", "median_seconds", "seconds_per_call"]

#: Repeats behind every median unless a suite says otherwise.
REPEATS = 5
#: Most calls made to warm up caches, allocators and lazy imports before timing.
WARMUP_CALLS = 200


def seconds_per_call(fn: Callable[[], Any], calls: int, *, repeats: int = REPEATS) -> float:
    """Median over ``repeats`` of the mean time (s) per call of ``calls`` calls to ``fn``."""
    if calls < 1 or repeats < 1:
        raise ValueError(f"calls and repeats must be at least 1, got {calls} and {repeats}")
    for _ in range(min(calls, WARMUP_CALLS)):
        fn()
    per_call = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(calls):
            fn()
        per_call.append((time.perf_counter() - t0) / calls)
    return statistics.median(per_call)


def median_seconds(samples: Iterable[float]) -> float:
    """Median of individually timed samples (s), for timings taken inside a running loop."""
    values = list(samples)
    if not values:
        raise ValueError("no timing samples to take the median of")
    return statistics.median(values)
