"""A wall-clock limit for one episode raised from within, where its process cannot be killed.

Local workers enforce ``--episode-timeout`` by killing the process that runs the episode
(:mod:`puckboard.sweep.host`), which stops anything. An episode run in this process
(:class:`~puckboard.sweep.executors.InlineExecutor`) or on a Dask worker, which puckboard
cannot kill, gets this limit instead, so that a controller that never returns (a
``while True`` in a student's layer) cannot stall a whole sweep there either.

The limit is enforced from a watchdog thread that raises :class:`WallTimeExceeded` in the
episode's thread (CPython's ``PyThreadState_SetAsyncExc``, the mechanism behind
asynchronous ``KeyboardInterrupt``). It works in Dask worker threads and in-process
alike, on every platform — unlike ``SIGALRM``, which is POSIX-only and main-thread-only.
The exception arrives at the next Python bytecode, so a controller blocked inside one
long C call (``time.sleep(1e9)``) is not stopped until that call returns; the episode
then still ends as an ``error`` row of kind ``timeout`` and the worker lives on.

Under a tracer (coverage, a debugger) the exception can arrive while the tracer's own
code runs. The episode is still stopped, but the tracer may not recover: on Python 3.11
coverage then hangs (coveragepy issue 1626). Measure coverage on sweeps without an
episode limit, or with controllers that return.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from typing import Any, TypeVar

__all__ = ["WallTimeExceeded", "call_with_wall_limit"]

log = logging.getLogger(__name__)

T = TypeVar("T")


class WallTimeExceeded(Exception):
    """An episode ran longer than its wall-clock limit."""


def _async_raiser() -> Callable[[int, Any], int] | None:
    try:
        import ctypes

        raise_in = ctypes.pythonapi.PyThreadState_SetAsyncExc
    except (ImportError, AttributeError):  # not CPython
        return None

    def set_async(thread_id: int, exc: Any) -> int:
        return int(
            raise_in(ctypes.c_ulong(thread_id), None if exc is None else ctypes.py_object(exc))
        )

    return set_async


def call_with_wall_limit(fn: Callable[[], T], seconds: float | None) -> T:
    """``fn()``, interrupted with :class:`WallTimeExceeded` after ``seconds`` of wall time.

    ``None`` means no limit. Where the interpreter cannot raise in a thread (not CPython)
    the limit is skipped with a warning.
    """
    if seconds is None:
        return fn()
    if not seconds > 0:
        raise ValueError(f"the wall-clock limit must be positive seconds, got {seconds}")
    set_async = _async_raiser()
    if set_async is None:
        log.warning("episode wall-clock limits need CPython; running without one")
        return fn()
    target = threading.get_ident()
    finished = threading.Event()
    fired = threading.Event()
    lock = threading.Lock()

    def watch() -> None:
        if finished.wait(seconds):
            return
        with lock:
            if finished.is_set():
                return
            fired.set()
            set_async(target, WallTimeExceeded)

    watchdog = threading.Thread(target=watch, name="puckboard-episode-limit", daemon=True)
    watchdog.start()
    try:
        return fn()
    except WallTimeExceeded:
        raise WallTimeExceeded(
            f"episode exceeded its wall-clock limit of {seconds:g} s (a controller that "
            "never returns?)"
        ) from None
    finally:
        with lock:
            finished.set()
        watchdog.join()
        if fired.is_set():
            set_async(target, None)  # drop the exception if it has not been raised yet
