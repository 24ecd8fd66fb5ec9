"""Where batches of episodes run: in this process, or in local worker processes.

Every executor takes the same picklable task — :func:`puckboard.sweep.worker.run_batch`
with a scene and a list of episode specs — and yields each batch's rows as it finishes,
in completion order. The sweep never depends on that order or on which worker ran a
batch, so every executor gives the same rows for the same plan (the Dask one is in
:mod:`puckboard.sweep.cluster`).

We deliberately schedule nothing ourselves: :class:`LocalExecutor` is a
``concurrent.futures.ProcessPoolExecutor`` and the Dask executor hands the tasks to
``dask.distributed``; the sweep only chooses the order and size of the tasks
(:func:`puckboard.sweep.run.make_batches`).

Local workers are started with the ``spawn`` method on every platform. It is the only
method on Windows and the default on macOS; using it on Linux too means a sweep behaves
the same everywhere and never forks a parent holding threads (progress bar, Dask client).
They are created with Ctrl-C ignored and end themselves when the parent is gone
(:mod:`puckboard.sweep.signals`): stopping them is the parent's decision alone.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import logging
import multiprocessing.context
import os
import sys
import time
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures.process import BrokenProcessPool
from typing import Any

from .signals import creating_processes, interrupts_ignored
from .worker import LocalStopFlag, init_local_worker

__all__ = [
    "InlineExecutor",
    "LocalExecutor",
    "SweepExecutor",
    "WorkerLostError",
    "available_cpus",
    "worker_context",
]

log = logging.getLogger(__name__)

# ProcessPoolExecutor refuses more than 61 workers on Windows (WaitForMultipleObjects).
_WINDOWS_MAX_WORKERS = 61


class WorkerLostError(RuntimeError):
    """A worker process died (crashed, killed, out of memory) while running a batch.

    An exception *inside* an episode never gets here — it becomes an ``error`` row; this
    is the process itself going away, which stops the sweep. Rows already finished are
    kept, so running the same sweep again resumes it.
    """


def available_cpus() -> int:
    """CPUs this process may use (respects affinity masks and container limits)."""
    count = getattr(os, "process_cpu_count", None)
    if count is not None:
        return max(1, count() or 1)
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return max(1, os.cpu_count() or 1)


class SweepExecutor(ABC):
    """Runs tasks ``fn(*args)`` and yields their results as they complete."""

    #: How many tasks run at once (used to size batches).
    workers: int

    @abstractmethod
    def run(self, fn: Callable[..., Any], tasks: Sequence[tuple[Any, ...]]) -> Iterator[Any]:
        """Submit every task now; return an iterator of their results in completion order.

        A :class:`KeyboardInterrupt` (Ctrl-C, or SIGTERM turned into one) leaves the
        tasks to the caller, who either collects what they still finish with
        :meth:`stop` or drops them with :meth:`cancel`. Closing the iterator early
        otherwise (an exception in the consumer) cancels the tasks not finished.
        """

    def stop(self, grace: float) -> Iterator[Any]:
        """After Ctrl-C: ask the running tasks to end after their current episode,
        yield what they return within ``grace`` seconds, then :meth:`cancel` the rest.

        Tasks that have not started are dropped. This is how a stopped sweep keeps
        every episode that finished, including those of batches still running.
        """
        self.cancel()
        return iter(())

    @abstractmethod
    def cancel(self) -> None:
        """Drop pending tasks and stop the running ones at once."""

    @contextlib.contextmanager
    def cancelled_on_error(self) -> Iterator[None]:
        """:meth:`cancel` on any exception but :class:`KeyboardInterrupt` (and on an
        iterator closed early), as :meth:`run` promises; Ctrl-C is left to the caller."""
        try:
            yield
        except KeyboardInterrupt:
            raise  # the caller stops or cancels
        except BaseException:
            self.cancel()
            raise

    @abstractmethod
    def close(self) -> None:
        """Release workers (and any cluster this executor started)."""

    def stop_flag(self) -> Callable[[], bool] | None:
        """A picklable flag the tasks ask before each episode; :meth:`stop` raises it
        (``None``: this executor runs nothing it could stop)."""
        return None

    def runnable_controller(self, spec: str) -> str:
        """The controller spec as workers can load it (see :class:`DaskExecutor`)."""
        return spec

    def __enter__(self) -> SweepExecutor:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class InlineExecutor(SweepExecutor):
    """Run tasks one by one in this process: for debugging a controller (breakpoints and
    tracebacks work as usual) and for tests. Same rows as the parallel executors."""

    workers = 1

    def run(self, fn: Callable[..., Any], tasks: Sequence[tuple[Any, ...]]) -> Iterator[Any]:
        for task in tasks:
            yield fn(*task)

    def cancel(self) -> None:
        pass

    def close(self) -> None:
        pass


class _WorkerProcess(multiprocessing.context.SpawnProcess):
    """A spawned process created with Ctrl-C ignored (see :mod:`.signals`)."""

    def start(self) -> None:
        with interrupts_ignored():
            super().start()


class _WorkerContext(multiprocessing.context.SpawnContext):
    Process = _WorkerProcess


def worker_context() -> multiprocessing.context.SpawnContext:
    """The ``spawn`` context whose processes never see the terminal's Ctrl-C."""
    return _WorkerContext()


class LocalExecutor(SweepExecutor):
    """A pool of ``workers`` local processes (default: every available CPU).

    The processes start with the first :meth:`run`, import what an episode needs once,
    and serve every later sweep on this executor until :meth:`close`.
    """

    def __init__(self, workers: int | None = None) -> None:
        if workers is not None and workers < 1:
            raise ValueError(f"--workers must be at least 1, got {workers}")
        count = workers or available_cpus()
        if sys.platform == "win32":
            count = min(count, _WINDOWS_MAX_WORKERS)
        self.workers = count
        self._pool: cf.ProcessPoolExecutor | None = None
        self._pending: set[cf.Future[Any]] = set()
        self._stop_event: Any = None
        self._alive: tuple[Any, Any] | None = None  # the pipe whose end-of-file ends workers

    def _ensure_pool(self) -> cf.ProcessPoolExecutor:
        if self._pool is None:
            context = worker_context()
            reader, writer = context.Pipe(duplex=False)
            self._alive = (reader, writer)
            self._stop_event = context.Event()
            self._pool = cf.ProcessPoolExecutor(
                max_workers=self.workers,
                mp_context=context,
                initializer=init_local_worker,
                initargs=(reader, self._stop_event),
            )
        return self._pool

    def start(self) -> LocalExecutor:
        """Create every worker process now, without waiting for them.

        They start up (a Python interpreter, then the imports an episode needs) while
        the caller prepares the sweep — loads the scene, checks the plan, reads the
        output file — instead of after. Returns the executor.
        """
        try:
            with creating_processes():  # the pool's threads too: see .signals
                pool = self._ensure_pool()
                # one no-op per worker: a pool creates a process for each task it cannot
                # give to an idle one, and none is idle before its interpreter has started
                for _ in range(self.workers):
                    pool.submit(int)
        except BaseException:  # Ctrl-C among the processes: none may outlive this
            self.cancel()
            raise
        return self

    def stop_flag(self) -> LocalStopFlag:
        return LocalStopFlag()

    def run(self, fn: Callable[..., Any], tasks: Sequence[tuple[Any, ...]]) -> Iterator[Any]:
        futures: list[cf.Future[Any]] = []
        self._pending = set()
        # creating_processes: the pool's threads too, see .signals
        with self.cancelled_on_error(), creating_processes():
            pool = self._ensure_pool()
            for task in tasks:  # the first submits may create the worker processes
                future = pool.submit(fn, *task)
                futures.append(future)
                self._pending.add(future)
        return self._results(futures)

    def _results(self, futures: list[cf.Future[Any]]) -> Iterator[Any]:
        with self.cancelled_on_error():
            for future in cf.as_completed(futures):
                self._pending.discard(future)
                try:
                    result = future.result()
                except BrokenProcessPool as exc:
                    raise WorkerLostError(f"a local worker process died: {exc}") from exc
                yield result

    def stop(self, grace: float) -> Iterator[Any]:
        pending, self._pending = self._pending, set()
        if self._stop_event is not None:
            self._stop_event.set()
        running = [f for f in pending if not f.cancel()]  # those a worker has taken
        try:
            for future in cf.as_completed(running, timeout=grace):
                if not future.cancelled() and future.exception() is None:
                    yield future.result()
        except cf.TimeoutError:
            log.info("stopping: %d batches still running after %.1f s", len(running), grace)
        finally:
            self.cancel()

    def cancel(self) -> None:
        pending, self._pending = self._pending, set()
        for future in pending:
            future.cancel()
        pool, self._pool = self._pool, None
        if pool is not None:
            # shutdown() and terminate_workers() forget the processes, so take them first
            processes = list((getattr(pool, "_processes", None) or {}).values())
            terminate = getattr(pool, "terminate_workers", None)  # Python >= 3.14
            if terminate is not None:
                terminate()
            else:
                pool.shutdown(wait=False, cancel_futures=True)
                for process in processes:
                    if process.is_alive():
                        process.terminate()
            _wait_exited(processes, timeout=5.0)
        self._close_pipe()

    def close(self) -> None:
        pool, self._pool = self._pool, None
        if pool is not None:
            pool.shutdown(wait=True, cancel_futures=True)
        self._close_pipe()

    def _close_pipe(self) -> None:
        alive, self._alive = self._alive, None
        for end in alive or ():
            end.close()


def _wait_exited(processes: Sequence[Any], timeout: float) -> None:
    """Wait until every process has exited (its sentinel is ready).

    Not ``join()``: the pool's own manager thread joins the same processes, and whichever
    thread reaps a child second sees no exit code yet; the sentinel is reliable.
    """
    from multiprocessing.connection import wait

    pending = {p.sentinel for p in processes}
    deadline = time.monotonic() + timeout
    while pending:
        left = deadline - time.monotonic()
        if left <= 0:
            log.warning("%d worker process(es) did not stop within %.0f s", len(pending), timeout)
            return
        pending -= set(wait(list(pending), timeout=left))
