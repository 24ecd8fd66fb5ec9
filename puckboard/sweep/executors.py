"""Where batches of episodes run: in this process, or in local worker processes.

Every executor takes the same picklable task — :func:`puckboard.sweep.worker.run_batch`
with a scene and a list of episode specs — and yields each batch's rows as it finishes,
in completion order. The sweep never depends on that order or on which worker ran a
batch, so every executor gives the same rows for the same plan (the Dask one is in
:mod:`puckboard.sweep.cluster`).

:class:`LocalExecutor` runs its own worker processes (hosts, :mod:`puckboard.sweep.host`)
rather than a ``concurrent.futures`` pool, for two things a pool cannot do. It enforces
an episode's wall-clock limit on the process that runs it: the process is killed and
replaced, that episode becomes a ``timeout`` error row and the rest of its batch runs on
— a layer asleep in ``time.sleep`` or blocked in C is stopped as surely as a busy loop.
A worker that dies during an episode (``os._exit``, a crash, the memory limit) costs
that episode, of kind ``exited`` or ``crashed``, and nothing else. And it keeps tasks of
different :class:`~puckboard.sweep.host.Isolation` in different processes. Which task
goes to which idle worker is the one decision it makes: first come, first served, a
worker keeping to its own isolation. The sweep chooses the order and size of the tasks
(:mod:`puckboard.sweep.batches`).

Local workers are started with the ``spawn`` method on every platform. It is the only
method on Windows and the default on macOS; using it on Linux too means a sweep behaves
the same everywhere and never forks a parent holding threads (progress bar, Dask client).
They are created with Ctrl-C ignored and end themselves when the parent is gone
(:mod:`puckboard.sweep.signals`): stopping them is the parent's decision alone.
"""

from __future__ import annotations

import contextlib
import logging
import multiprocessing.context
import os
import sys
import time
from abc import ABC, abstractmethod
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from typing import Any

from .host import FRESH, Host, Isolation, Task
from .signals import creating_processes, interrupts_ignored, stops_held
from .worker import LocalStopFlag, LostUnit

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
    """A worker process died (crashed, killed, out of memory) outside any episode.

    An exception *inside* an episode never gets here — it becomes an ``error`` row — and
    neither does a local worker that dies during an episode (that episode's row says
    so); this is the process going away while doing the sweep's own work, which stops
    the sweep. Rows already finished are kept, so running the same sweep again resumes
    it.
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
    #: Whether :meth:`run`'s ``unit_limit`` is enforced on the process running the unit
    #: (it is killed and replaced) and its ``isolation`` kept. Where not, a sweep asks
    #: each episode to watch its own time instead (:mod:`puckboard.sweep.watchdog`),
    #: which cannot stop a layer blocked in C.
    stops_processes: bool = False

    @abstractmethod
    def run(
        self,
        fn: Callable[..., Any],
        tasks: Sequence[tuple[Any, ...]],
        *,
        isolation: Sequence[Isolation | None] | None = None,
        unit_limit: float | None = None,
    ) -> Iterator[Any]:
        """Submit every task now; return an iterator of their results in completion order.

        ``isolation`` (one per task) and ``unit_limit`` (wall-clock seconds per unit a
        task reports) are kept by executors that :attr:`stops_processes`, and ignored by
        the others.

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

    def run(
        self,
        fn: Callable[..., Any],
        tasks: Sequence[tuple[Any, ...]],
        *,
        isolation: Sequence[Isolation | None] | None = None,
        unit_limit: float | None = None,
    ) -> Iterator[Any]:
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

    The processes start with the first :meth:`run` (or :meth:`start`), import what an
    episode needs once, and serve every later sweep on this executor until :meth:`close`.
    A unit (an episode of a batch) that runs past :meth:`run`'s ``unit_limit``, or whose
    process dies, costs its process, not the run: see the module docstring.
    """

    stops_processes = True

    def __init__(self, workers: int | None = None) -> None:
        if workers is not None and workers < 1:
            raise ValueError(f"--workers must be at least 1, got {workers}")
        count = workers or available_cpus()
        if sys.platform == "win32":
            count = min(count, _WINDOWS_MAX_WORKERS)
        self.workers = count
        self._context = worker_context()
        self._hosts: list[Host] = []
        self._queue: deque[Task] = deque()  # tasks not yet given to a host, in order
        self._done: deque[tuple[Task, Any, BaseException | None]] = deque()
        self._open: set[Task] = set()  # tasks of the current run not yet handed back
        self._numbers = iter(range(sys.maxsize))
        self._unit_limit: float | None = None
        self._stopping = False
        self._stop_event: Any = None
        self._alive: tuple[Any, Any] | None = None  # the pipe whose end-of-file ends workers

    # -- processes ---------------------------------------------------------------------
    def _spawn(self, isolation: Isolation | None) -> Host:
        with creating_processes():  # the pipe and the event too: see .signals
            if self._alive is None:
                reader, writer = self._context.Pipe(duplex=False)
                self._alive = (reader, writer)
                self._stop_event = self._context.Event()
            host = Host(self._context, self._alive[0], self._stop_event, isolation)
        self._hosts.append(host)
        return host

    def _drop(self, host: Host) -> None:
        """End ``host`` now and forget it."""
        if host in self._hosts:
            self._hosts.remove(host)
        host.kill()

    def start(self) -> LocalExecutor:
        """Create every worker process now, without waiting for them.

        They start up (a Python interpreter, then the imports an episode needs) while
        the caller prepares the sweep — loads the scene, checks the plan, reads the
        output file — instead of after. Returns the executor.
        """
        try:
            while len(self._hosts) < self.workers:
                self._spawn(FRESH)
        except BaseException:  # Ctrl-C among the processes: none may outlive this
            self.cancel()
            raise
        return self

    def stop_flag(self) -> LocalStopFlag:
        return LocalStopFlag()

    # -- running -----------------------------------------------------------------------
    def run(
        self,
        fn: Callable[..., Any],
        tasks: Sequence[tuple[Any, ...]],
        *,
        isolation: Sequence[Isolation | None] | None = None,
        unit_limit: float | None = None,
    ) -> Iterator[Any]:
        if unit_limit is not None and not unit_limit > 0:
            raise ValueError(
                f"a unit's wall-clock limit must be positive seconds, got {unit_limit}"
            )
        isolations = list(isolation) if isolation is not None else [None] * len(tasks)
        if len(isolations) != len(tasks):
            raise ValueError(f"{len(isolations)} isolations given for {len(tasks)} tasks")
        self._unit_limit = unit_limit
        self._stopping = False
        self._done.clear()
        made = [
            Task(next(self._numbers), fn, tuple(args), iso) for args, iso in zip(tasks, isolations)
        ]
        self._queue.extend(made)
        self._open = set(made)
        with self.cancelled_on_error():
            self._dispatch()  # the first tasks may create the worker processes
        return self._results()

    def _results(self) -> Iterator[Any]:
        with self.cancelled_on_error():
            while self._open:
                while self._done:
                    task, value, error = self._done.popleft()
                    self._open.discard(task)
                    if error is not None:
                        raise error
                    yield value
                if self._open:
                    self._step(None)

    def _step(self, timeout: float | None) -> None:
        """Start what can start, wait for news from the workers (or a unit's deadline, or
        ``timeout`` seconds), and act on it."""
        from multiprocessing.connection import wait

        if not self._stopping:
            self._dispatch()
        busy = [h for h in self._hosts if h.task is not None]
        deadlines = [h.task.deadline for h in busy if h.task and h.task.deadline is not None]
        if deadlines:
            due = max(0.0, min(deadlines) - time.monotonic())
            timeout = due if timeout is None else min(timeout, due)
        if not busy and not self._stopping and self._open:
            # open tasks, none running and none left to start: they were lost track of
            raise RuntimeError(f"{len(self._open)} tasks neither queued nor running")
        watched: list[Any] = [h.conn for h in busy] + [h.sentinel for h in self._hosts]
        ready = wait(watched, timeout) if watched else []
        for host in list(self._hosts):
            if host.conn in ready or host.sentinel in ready:
                self._read(host)
        self._enforce_deadlines()

    def _read(self, host: Host) -> None:
        """Act on every message ``host`` has sent; a host that has died (or whose pipe
        broke) is dropped, and what it was running is lost."""
        gone = False
        with stops_held():  # a message read half-way would leave the pipe unreadable
            try:
                while host.conn.poll():
                    self._handle(host, host.conn.recv())
            except Exception:  # end-of-file, a broken pipe or message: the host is gone
                gone = True
        if gone or not host.process.is_alive():
            self._lost(host, f"{host.exit_description()} during this episode")

    def _handle(self, host: Host, message: tuple[Any, ...]) -> None:
        task = host.task
        if task is None or message[1] != task.number:
            return
        kind = message[0]
        if kind == "began":
            task.current = int(message[2])
            limit = self._unit_limit
            task.deadline = None if limit is None else time.monotonic() + limit
        elif kind == "unit":
            task.units.append(message[3])
            task.current = task.deadline = None
        elif kind == "done":
            host.task = None
            value = message[2]
            resumed = task.start > 0 or task.prefix
            self._done.append((task, [*task.finished_units(), *value] if resumed else value, None))
        elif kind == "failed":
            host.task = None
            self._done.append((task, None, message[2]))

    def _lost(self, host: Host, why: str, kind: str | None = None) -> None:
        """``host`` is gone (``why``): the unit it was running is lost, of ``kind`` (by
        default by how the process ended), and its task goes on from the next unit."""
        task = host.task
        host.task = None
        code = host.process.exitcode
        self._drop(host)
        if task is None:
            return
        if task.current is None:  # not inside a unit: nothing to blame but the worker
            self._done.append((task, None, WorkerLostError(f"a local worker process died: {why}")))
            return
        if kind is None:
            code = host.process.exitcode if code is None else code
            kind = "exited" if code is not None and code >= 0 else "crashed"
        self._retry(task, LostUnit(kind, why))

    def _retry(self, task: Task, lost: LostUnit) -> None:
        """Run ``task`` again from its lost unit on, which becomes an error row of the
        loss's kind; while stopping, hand back the units it finished instead."""
        assert task.current is not None
        task.prefix.extend(task.units)
        task.start = task.current
        task.kwargs = {**task.kwargs, "start": task.start, "lost": lost}
        task.units = []
        task.current = task.deadline = None
        if self._stopping:
            self._done.append((task, task.finished_units(), None))
        else:
            self._queue.appendleft(task)

    def _enforce_deadlines(self) -> None:
        now = time.monotonic()
        for host in list(self._hosts):
            task = host.task
            if task is None or task.deadline is None or now < task.deadline:
                continue
            self._read(host)  # it may have finished just now
            if host.task is task and task.deadline is not None and task.current is not None:
                limit = self._unit_limit or 0.0
                self._lost(
                    host,
                    f"the episode ran past its wall-clock limit of {limit:g} s and its "
                    "process was stopped (a layer that sleeps, blocks or never returns?)",
                    kind="timeout",
                )

    # -- which task where --------------------------------------------------------------
    def _dispatch(self) -> None:
        """Give queued tasks to idle workers of their isolation, create workers while
        there are fewer than :attr:`workers`, and let an idle worker of another
        isolation make way for a new one when there are not."""
        while self._queue:
            for host in [h for h in self._hosts if h.task is None]:
                task = self._pick(host)
                if task is not None:
                    self._assign(host, task)
            if not self._queue:
                return
            task = self._for_new_worker()
            if task is not None and len(self._hosts) < self.workers:
                self._assign(self._spawn(task.isolation), task)
                continue
            idle = [h for h in self._hosts if h.task is None]
            if not idle:
                return
            self._drop(idle[0])  # an isolation of its own, with nothing left to run

    def _held(self) -> list[Isolation | None]:
        return [h.isolation for h in self._hosts if h.isolation is not FRESH]

    def _pick(self, host: Host) -> Task | None:
        """The first queued task ``host`` may run; a fresh host prefers an isolation no
        other worker serves, so that the workers spread over the submissions."""
        if host.isolation is FRESH:
            return self._for_new_worker()
        return next((t for t in self._queue if t.isolation == host.isolation), None)

    def _for_new_worker(self) -> Task | None:
        if not self._queue:
            return None
        held = self._held()
        return next((t for t in self._queue if t.isolation not in held), self._queue[0])

    def _assign(self, host: Host, task: Task) -> None:
        self._queue.remove(task)
        try:
            with stops_held():
                host.assign(task)
        except (OSError, ValueError):  # it died before it could take the task
            host.task = None
            self._queue.appendleft(task)
            self._drop(host)

    # -- stopping ----------------------------------------------------------------------
    def request_stop(self) -> None:
        """Ask the running tasks to end after their current unit (from any thread); what
        they return is yielded as usual. :meth:`cancel` clears the request."""
        if self._stop_event is not None:
            self._stop_event.set()

    def stop(self, grace: float) -> Iterator[Any]:
        self._stopping = True
        if self._stop_event is not None:
            self._stop_event.set()
        self._queue.clear()
        deadline = time.monotonic() + grace
        try:
            while True:
                while self._done:
                    task, value, error = self._done.popleft()
                    self._open.discard(task)
                    if error is None:
                        yield value
                busy = [h for h in self._hosts if h.task is not None]
                left = deadline - time.monotonic()
                if not busy or left <= 0:
                    break
                self._step(left)
            for host in self._hosts:  # still running: the episodes they finished
                if host.task is not None and host.task.finished_units():
                    yield host.task.finished_units()
            if any(h.task is not None for h in self._hosts):
                log.info("stopping: batches still running after %.1f s", grace)
        finally:
            self.cancel()

    def cancel(self) -> None:
        self._queue.clear()
        self._done.clear()
        self._open = set()
        hosts, self._hosts = self._hosts, []
        for host in hosts:
            if host.process.is_alive():
                host.process.kill()
        for host in hosts:
            host.kill()
        self._close_pipe()

    def close(self) -> None:
        hosts, self._hosts = self._hosts, []
        for host in hosts:
            if host.task is None:
                with contextlib.suppress(OSError, ValueError):
                    host.conn.send(("exit",))
        deadline = time.monotonic() + 5.0
        for host in hosts:
            host.process.join(max(0.0, deadline - time.monotonic()))
            host.kill()
        self._queue.clear()
        self._open = set()
        self._close_pipe()

    def _close_pipe(self) -> None:
        alive, self._alive = self._alive, None
        self._stop_event = None
        for end in alive or ():
            end.close()
