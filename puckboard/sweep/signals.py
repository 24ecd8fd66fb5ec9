"""How a sweep meets Ctrl-C and SIGTERM: the parent decides, the workers never see them.

A terminal's Ctrl-C sends SIGINT to every process of the foreground group, so worker
processes would get it too: each would die with its own ``KeyboardInterrupt`` traceback
half-way through a result, and a pool (or a Dask nanny) would then wait for, or restart,
workers that are gone. Instead the workers ignore SIGINT from their first instruction and
the parent stops them itself, keeping every finished row:

* :func:`interrupts_ignored` wraps the creation of a worker process. On POSIX a signal
  ignored by a parent stays ignored in a child across ``exec``, and Python then leaves it
  ignored, so the child never sees a Ctrl-C, not even while it is still importing. The
  parent meanwhile holds a Ctrl-C back rather than losing it (:func:`creating_processes`)
  and raises it once the processes exist, so that it can end them. On Windows, or from a
  thread other than the main one, both do nothing and the worker ignores SIGINT once its
  initializer runs.
* :func:`spare_native_threads` imports numpy with Ctrl-C blocked. The worker threads its
  BLAS library starts on import (one per core, outside Python's reach) then block SIGINT
  for life. Otherwise a Ctrl-C that comes while a worker is being created, when SIGINT
  is ignored process-wide for the child's sake, could be taken by such a thread and
  discarded: the command would carry on as if no Ctrl-C had come.
* :func:`stop_on_terminate` makes SIGTERM (``kill PID``, a service manager stopping the
  command) take the same orderly path as Ctrl-C, by raising :class:`Terminated` — a
  :class:`KeyboardInterrupt` — in the main thread. Without it SIGTERM ends the parent on
  the spot: rows not yet flushed are lost and workers are orphaned.

Workers also watch their parent (:func:`puckboard.sweep.worker.init_local_worker`), so that
even a parent killed outright (SIGKILL, a crash) leaves no process behind.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
from collections.abc import Iterator
from types import FrameType

__all__ = [
    "Terminated",
    "creating_processes",
    "interrupts_deferred",
    "interrupts_ignored",
    "spare_native_threads",
    "stop_on_terminate",
    "stops_held",
]


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised where Ctrl-C would raise :class:`KeyboardInterrupt`.

    It is one, so everything that stops cleanly on Ctrl-C does so on SIGTERM too; the
    command line reports it as ``terminated`` with the conventional status 128 + 15.
    """

    reason = "terminated"
    exit_status = 128 + 15


def _in_main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


@contextlib.contextmanager
def interrupts_deferred() -> Iterator[None]:
    """Hold Ctrl-C back until the block ends (POSIX, main thread), then raise it.

    SIGINT is blocked in this thread, and threads started inside the block inherit
    that, so a Ctrl-C meanwhile stays pending instead of reaching a thread where
    :func:`interrupts_ignored` would drop it; it is delivered, as a
    :class:`KeyboardInterrupt`, when the block ends.
    """
    if os.name != "posix" or not _in_main_thread():
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


@contextlib.contextmanager
def stops_held() -> Iterator[None]:
    """Hold Ctrl-C and SIGTERM back until the block ends (POSIX, main thread), then raise
    them: around a short step that must not be cut in two, such as reading one message
    from a worker's pipe (cut between its length and its body, the pipe could not be
    read again). Creates no process: a child would inherit SIGTERM blocked."""
    if os.name != "posix" or not _in_main_thread():
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


@contextlib.contextmanager
def creating_processes() -> Iterator[None]:
    """Around code that creates worker processes (and their pipes and events): Ctrl-C
    deferred until it is done, so that the processes exist when it is handled."""
    if os.name == "posix" and _in_main_thread():
        # multiprocessing starts its resource tracker with the first process or
        # semaphore and unblocks SIGINT in the calling thread when it has, which would
        # end the deferral early: start it first
        from multiprocessing import resource_tracker

        resource_tracker.ensure_running()
    with interrupts_deferred():
        yield


def spare_native_threads() -> None:
    """Import numpy with Ctrl-C held back (POSIX, main thread), once, before anything else
    does, so the native threads it starts block SIGINT (see the module's docstring).

    Called by the command line before it runs a command. A Ctrl-C during the import is
    raised when it ends. Where numpy is already imported its threads are as they were
    started, and nothing changes.
    """
    if "numpy" in sys.modules:
        return
    with interrupts_deferred():
        import numpy  # noqa: F401  (the import is the point: its threads start now)


@contextlib.contextmanager
def interrupts_ignored() -> Iterator[None]:
    """Ignore SIGINT while a process started inside the block is created (POSIX).

    The process keeps it ignored for life. This process loses no Ctrl-C meanwhile: the
    block runs within :func:`creating_processes`, and one already pending is raised
    before anything is created (setting SIG_IGN would discard it).
    """
    if os.name != "posix" or not _in_main_thread():
        yield  # Windows: no ignored signals to inherit; elsewhere: not allowed from here
        return
    with creating_processes():
        if signal.SIGINT in signal.sigpending():
            signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})  # raises it
        previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
        try:
            yield
        finally:
            signal.signal(signal.SIGINT, signal.SIG_DFL if previous is None else previous)


@contextlib.contextmanager
def stop_on_terminate() -> Iterator[None]:
    """Within the block, SIGTERM raises :class:`Terminated` in the main thread.

    Does nothing outside the main thread (where Python cannot install handlers) or where
    the platform has no SIGTERM; the previous handler is restored afterwards.
    """
    sigterm = getattr(signal, "SIGTERM", None)
    if sigterm is None or not _in_main_thread():
        yield
        return

    def terminate(signum: int, frame: FrameType | None) -> None:
        raise Terminated

    previous = signal.signal(sigterm, terminate)
    try:
        yield
    finally:
        signal.signal(sigterm, signal.SIG_DFL if previous is None else previous)
