"""Where batches of episodes run: local processes, or an existing Dask cluster.

Both executors take the same picklable task — :func:`puckboard.sweep.worker.run_batch`
with a scene and a list of episode specs — and yield each batch's rows as it finishes,
in completion order. The sweep never depends on that order or on which worker ran a
batch, so both executors give the same rows for the same plan.

We deliberately schedule nothing ourselves: :class:`LocalExecutor` is a
``concurrent.futures.ProcessPoolExecutor`` and :class:`DaskExecutor` hands the tasks to
``dask.distributed``, which already does load balancing, worker loss and dashboards.

Local workers are started with the ``spawn`` method on every platform. It is the only
method on Windows and the default on macOS; using it on Linux too means a sweep behaves
the same everywhere and never forks a parent holding threads (progress bar, Dask client).
"""

from __future__ import annotations

import concurrent.futures as cf
import logging
import multiprocessing
import os
import sys
import time
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures.process import BrokenProcessPool
from typing import Any

from .worker import ignore_interrupts

__all__ = [
    "DaskExecutor",
    "DaskStopFlag",
    "InlineExecutor",
    "LocalExecutor",
    "SweepExecutor",
    "WorkerLostError",
    "available_cpus",
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
        """Submit every task; yield results in completion order.

        Closing the iterator early (an exception, Ctrl-C in the consumer) cancels the
        tasks that have not finished.
        """

    @abstractmethod
    def cancel(self) -> None:
        """Drop pending tasks and stop the running ones as fast as possible."""

    @abstractmethod
    def close(self) -> None:
        """Release workers (and any cluster this executor started)."""

    def stop_flag(self) -> Callable[[], bool] | None:
        """A flag the tasks ask between episodes, for executors that cannot kill a
        running task (``None``: this executor stops its workers itself)."""
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


class LocalExecutor(SweepExecutor):
    """A pool of ``workers`` local processes (default: every available CPU)."""

    def __init__(self, workers: int | None = None) -> None:
        if workers is not None and workers < 1:
            raise ValueError(f"--workers must be at least 1, got {workers}")
        count = workers or available_cpus()
        if sys.platform == "win32":
            count = min(count, _WINDOWS_MAX_WORKERS)
        self.workers = count
        self._pool: cf.ProcessPoolExecutor | None = None
        self._pending: list[cf.Future[Any]] = []

    def _ensure_pool(self) -> cf.ProcessPoolExecutor:
        if self._pool is None:
            self._pool = cf.ProcessPoolExecutor(
                max_workers=self.workers,
                mp_context=multiprocessing.get_context("spawn"),
                initializer=ignore_interrupts,
            )
        return self._pool

    def run(self, fn: Callable[..., Any], tasks: Sequence[tuple[Any, ...]]) -> Iterator[Any]:
        pool = self._ensure_pool()
        futures = [pool.submit(fn, *task) for task in tasks]
        self._pending = futures
        finished = False
        try:
            for future in cf.as_completed(futures):
                try:
                    result = future.result()
                except BrokenProcessPool as exc:
                    raise WorkerLostError(f"a local worker process died: {exc}") from exc
                yield result
            finished = True
        finally:
            if not finished:
                self.cancel()
            self._pending = []

    def cancel(self) -> None:
        for future in self._pending:
            future.cancel()
        pool, self._pool = self._pool, None
        if pool is None:
            return
        terminate = getattr(pool, "terminate_workers", None)  # Python >= 3.14
        if terminate is not None:
            terminate()
            return
        # shutdown() forgets the worker processes, so take them first.
        processes = list((getattr(pool, "_processes", None) or {}).values())
        pool.shutdown(wait=False, cancel_futures=True)
        for process in processes:
            if process.is_alive():
                process.terminate()
        _wait_exited(processes, timeout=5.0)

    def close(self) -> None:
        pool, self._pool = self._pool, None
        if pool is not None:
            pool.shutdown(wait=True, cancel_futures=True)


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


class DaskStopFlag:
    """Picklable "has the sweep been stopped?" flag backed by a named Dask ``Event``.

    Dask cannot interrupt a task that is running, so a stopped sweep would leave every
    busy worker on its batch until the batch ends. Each batch asks this flag before each
    episode (:func:`~puckboard.sweep.worker.run_batch`), so a worker is free again one
    episode after :meth:`DaskExecutor.cancel`. Asking costs one round trip to the
    scheduler, small next to an episode.
    """

    def __init__(self, name: str) -> None:
        self.name = name
        self._event: Any = None

    def __call__(self) -> bool:
        if self._event is None:
            from distributed import Event

            self._event = Event(self.name)  # on a worker: the worker's own client
        return bool(self._event.is_set())

    def __getstate__(self) -> dict[str, Any]:
        return {"name": self.name}  # the Event holds a client: rebuild it where unpickled

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.name = state["name"]
        self._event = None


class DaskExecutor(SweepExecutor):
    """Run tasks on a Dask cluster: an existing one at ``scheduler``, or a local one.

    ``scheduler`` is an address such as ``tcp://10.0.0.5:8786`` (start a cluster with
    ``dask scheduler`` and ``dask worker tcp://...`` on each machine; puckboard must be
    installed on every worker). Without an address a ``LocalCluster`` of
    ``local_workers`` single-threaded worker processes is started here and shut down by
    :meth:`close` — handy for tests and benchmarks.

    Controllers given as ``path/file.py:factory`` are uploaded to an external cluster's
    workers (``Client.upload_file``), since those machines may not see our files.
    """

    def __init__(
        self,
        scheduler: str | None = None,
        *,
        local_workers: int | None = None,
        timeout: float = 30.0,
        quiet: bool = True,
    ) -> None:
        try:
            from dask.distributed import Client, LocalCluster
        except ImportError as exc:
            raise ImportError(
                "running on a Dask cluster needs dask.distributed: pip install 'puckboard[dask]'"
            ) from exc
        self.scheduler = scheduler
        self._cluster: Any = None
        self.client: Any = None
        # dask.distributed logs every scheduler, worker and connection start and stop at
        # INFO on its own handler; ``quiet`` keeps that to warnings while we use it.
        self._dask_log = logging.getLogger("distributed")
        self._dask_log_level = self._dask_log.level
        if quiet and self._dask_log.getEffectiveLevel() < logging.WARNING:
            self._dask_log.setLevel(logging.WARNING)
        try:
            if scheduler is None:
                self._cluster = LocalCluster(
                    n_workers=local_workers or available_cpus(),
                    threads_per_worker=1,
                    processes=True,
                    dashboard_address=None,
                    host="127.0.0.1",
                    silence_logs=logging.ERROR,
                )
                self.client = Client(self._cluster)
            else:
                self.client = Client(scheduler, timeout=min(timeout, 10.0))
            self.client.wait_for_workers(1, timeout=timeout)
        except (OSError, TimeoutError) as exc:
            self._shutdown()
            where = scheduler or "a local cluster"
            raise ConnectionError(
                f"cannot use the Dask scheduler at {where}: {exc}. Is it running and are "
                "workers connected? (dask scheduler; dask worker ADDRESS)"
            ) from exc
        self.workers = max(1, sum(self.client.nthreads().values()))
        self._futures: list[Any] = []
        self._uploaded: dict[str, str] = {}
        self._stop_name = _new_stop_name()

    def stop_flag(self) -> DaskStopFlag:
        return DaskStopFlag(self._stop_name)

    def runnable_controller(self, spec: str) -> str:
        from ..behaviours.presets import split_file_spec

        found = split_file_spec(spec)
        if found is None or self._cluster is not None:
            return spec
        if spec not in self._uploaded:
            path, attr = found
            module = path.stem
            clash = [s for s, m in self._uploaded.items() if m.split(":")[0] == module]
            if clash:
                raise ValueError(
                    f"controller files {clash[0]!r} and {spec!r} share the module name "
                    f"{module!r}; rename one to run both on a remote cluster"
                )
            self.client.upload_file(str(path))
            self._uploaded[spec] = f"{module}:{attr}"
        return self._uploaded[spec]

    def run(self, fn: Callable[..., Any], tasks: Sequence[tuple[Any, ...]]) -> Iterator[Any]:
        from dask.distributed import as_completed
        from distributed.scheduler import KilledWorker

        futures = [self.client.submit(fn, *task, pure=False) for task in tasks]
        self._futures = futures
        finished = False
        try:
            for future in as_completed(futures):
                try:
                    result = future.result()
                except KilledWorker as exc:
                    raise WorkerLostError(f"Dask workers died running a batch: {exc}") from exc
                yield result
                future.release()
            finished = True
        finally:
            if not finished:
                self.cancel()
            self._futures = []

    def cancel(self) -> None:
        """Drop waiting batches and tell running ones to stop after their episode.

        The flag is then renamed, so a later sweep on this executor starts unstopped.
        """
        if self._futures:
            from distributed import Event

            Event(self._stop_name, client=self.client).set()
            self._stop_name = _new_stop_name()
            self.client.cancel(self._futures)
            self._futures = []

    def close(self) -> None:
        self.cancel()
        self._shutdown()

    def _shutdown(self) -> None:
        client = getattr(self, "client", None)
        if client is not None:
            client.close()
            self.client = None
        if self._cluster is not None:
            self._cluster.close()
            self._cluster = None
        self._dask_log.setLevel(self._dask_log_level)


def _new_stop_name() -> str:
    """A name no other sweep on the same Dask cluster uses."""
    import uuid

    return f"puckboard-sweep-stop-{uuid.uuid4().hex}"
