"""Run a sweep's batches on a Dask cluster: an existing one, or a local one of our own.

Dask cannot interrupt a task that is running, so a stopped sweep asks its batches to
end instead: each batch asks a stop flag (:class:`DaskStopFlag`, a named Dask ``Event``)
before each episode, and :meth:`DaskExecutor.stop` collects what they return.

A local cluster (:class:`DaskExecutor` without an address) runs in a host process of its
own, created with Ctrl-C ignored (:mod:`puckboard.sweep.signals`); its scheduler, nannies
and workers inherit that, so a Ctrl-C in the terminal reaches only the sweep, which stops
the cluster itself. Created in the sweep's own process, the cluster's worker processes
would each die of the Ctrl-C with a traceback and leave their nannies waiting for them.
The host closes the cluster when told to, or when the sweep's process is gone.

Dask cannot kill a task either. Where a run asks for an episode's wall-clock limit to be
kept on the process, or for tasks kept apart (:class:`~puckboard.sweep.host.Isolation`),
each task runs instead in a host process of the Dask worker's own
(:func:`run_hosted`: a one-worker :class:`~puckboard.sweep.executors.LocalExecutor` per
worker thread), which the worker kills and replaces as a local sweep does. That needs
workers allowed to start processes, which Dask's nanny forbids by default (its workers
are daemon processes): start them with ``DASK_DISTRIBUTED__WORKER__DAEMON=False``, or
with ``--no-nanny``. :attr:`DaskExecutor.stops_processes` says whether they can; the
local cluster of our own is started so that they can.
"""

from __future__ import annotations

import contextlib
import hashlib
import logging
import re
import shutil
import signal
import tempfile
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

from .executors import (
    LocalExecutor,
    SweepExecutor,
    WorkerLostError,
    available_cpus,
    worker_context,
)
from .host import Isolation
from .worker import LocalStopFlag

__all__ = ["ClusterSetupError", "DaskExecutor", "DaskStopFlag", "run_hosted"]

#: What to tell a user whose Dask workers may not start processes.
DAEMON_FIX = (
    "start the workers so that they may: DASK_DISTRIBUTED__WORKER__DAEMON=False dask worker "
    "ADDRESS (or dask worker ADDRESS --no-nanny)"
)


class ClusterSetupError(RuntimeError):
    """The Dask cluster cannot do what the run needs; the message says how to start it."""


log = logging.getLogger(__name__)


class DaskStopFlag:
    """Picklable "has the sweep been stopped?" flag backed by a named Dask ``Event``.

    Each batch asks it before each episode (:func:`~puckboard.sweep.worker.run_batch`),
    so a worker is free again one episode after :meth:`DaskExecutor.stop` or
    :meth:`DaskExecutor.cancel`. Asking costs one round trip to the scheduler, small next
    to an episode.
    """

    def __init__(self, name: str) -> None:
        self.name = name
        self._event: Any = None

    def __call__(self) -> bool:
        if self._event is None:
            from distributed import Event, get_worker

            try:
                get_worker()
            except ValueError:  # in a host a worker started (run_hosted): its pool's flag
                return LocalStopFlag()()
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
    ``local_workers`` single-threaded worker processes is started in a host process and
    shut down by :meth:`close` — handy for tests and benchmarks.

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
            from dask.distributed import Client
        except ImportError as exc:
            raise ImportError(
                "running on a Dask cluster needs dask.distributed: pip install 'puckboard[dask]'"
            ) from exc
        self.scheduler = scheduler
        self._host: _ClusterHost | None = None
        self.client: Any = None
        self._futures: dict[str, Any] = {}
        # dask.distributed logs every scheduler, worker and connection start and stop at
        # INFO on its own handler; ``quiet`` keeps that to warnings while we use it.
        self._dask_log = logging.getLogger("distributed")
        self._dask_log_level = self._dask_log.level
        if quiet and self._dask_log.getEffectiveLevel() < logging.WARNING:
            self._dask_log.setLevel(logging.WARNING)
        try:
            if scheduler is None:
                self._host = _ClusterHost(local_workers or available_cpus(), timeout)
            address = scheduler if self._host is None else self._host.address
            self.client = Client(address, timeout=min(timeout, 10.0))
            self.client.wait_for_workers(1, timeout=timeout)
        except (OSError, TimeoutError) as exc:
            self._shutdown()
            where = scheduler or "a local cluster"
            raise ConnectionError(
                f"cannot use the Dask scheduler at {where}: {exc}. Is it running and are "
                "workers connected? (dask scheduler; dask worker ADDRESS)"
            ) from exc
        except BaseException:
            self._shutdown()
            raise
        self.workers = max(1, sum(self.client.nthreads().values()))
        #: whether every worker may start processes, as an episode's limit on the process
        #: and isolation need (see the module docstring)
        self.stops_processes = all(self.client.run(_may_start_processes).values())
        self._uploaded: dict[str, str] = {}
        self._stop_name = _new_stop_name()

    def stop_flag(self) -> DaskStopFlag:
        return DaskStopFlag(self._stop_name)

    def runnable_controller(self, spec: str) -> str:
        from ..behaviours.presets import split_file_spec

        found = split_file_spec(spec)
        if found is None or self._host is not None:
            return spec
        if spec not in self._uploaded:
            path, attr = found
            # a module name of its own (two students' controller.py, two versions of one)
            digest = hashlib.sha256(path.read_bytes()).hexdigest()[:10]
            module = f"{re.sub(r'[^0-9A-Za-z_]', '_', path.stem)}_{digest}"
            with tempfile.TemporaryDirectory() as folder:
                copy = Path(folder) / f"{module}.py"
                shutil.copyfile(path, copy)
                self.client.upload_file(str(copy))
            self._uploaded[spec] = f"{module}:{attr}"
        return self._uploaded[spec]

    def run(
        self,
        fn: Callable[..., Any],
        tasks: Sequence[tuple[Any, ...]],
        *,
        isolation: Sequence[Isolation | None] | None = None,
        unit_limit: float | None = None,
    ) -> Iterator[Any]:
        hosted = isolation is not None or unit_limit is not None
        if hosted and not self.stops_processes:
            raise ClusterSetupError(
                "this run keeps each episode's wall-clock limit on its process and "
                "submissions apart, which needs Dask workers that may start processes: "
                f"{DAEMON_FIX}"
            )
        futures: dict[str, Any] = {}
        self._futures = futures
        with self.cancelled_on_error():
            for index, task in enumerate(tasks):
                if hosted:
                    apart = None if isolation is None else isolation[index]
                    future = self.client.submit(
                        run_hosted, fn, task, apart, unit_limit, self.stop_flag(), pure=False
                    )
                else:
                    future = self.client.submit(fn, *task, pure=False)
                futures[future.key] = future
        return self._results(futures)

    def _results(self, futures: dict[str, Any]) -> Iterator[Any]:
        from dask.distributed import as_completed
        from distributed.scheduler import KilledWorker

        with self.cancelled_on_error():
            for future in as_completed(list(futures.values())):
                futures.pop(future.key, None)
                try:
                    result = future.result()
                except KilledWorker as exc:
                    raise WorkerLostError(f"Dask workers died running a batch: {exc}") from exc
                future.release()
                yield result

    def stop(self, grace: float) -> Iterator[Any]:
        """Raise the stop flag, collect the batches that end within ``grace`` seconds
        (those not started end at once, with no rows), cancel the rest."""
        futures = list(self._futures.values())
        if not futures:
            return
        from dask.distributed import as_completed

        self._raise_stop_flag()
        try:
            for future in as_completed(futures, timeout=grace):
                self._futures.pop(future.key, None)
                if future.status == "finished":
                    yield future.result()
        except TimeoutError:
            log.info("stopping: %d batches still running after %.1f s", len(self._futures), grace)
        finally:
            self.cancel()

    def cancel(self) -> None:
        """Drop waiting batches and tell running ones to stop after their episode."""
        futures = list(self._futures.values())
        self._futures = {}
        if futures and self.client is not None:
            self._raise_stop_flag()
            self.client.cancel(futures)

    def _raise_stop_flag(self) -> None:
        """Set the flag the running batches were given, and take a fresh name for the
        next sweep on this executor, which must start unstopped."""
        from distributed import Event

        Event(self._stop_name, client=self.client).set()
        self._stop_name = _new_stop_name()

    def close(self) -> None:
        self.cancel()
        self._shutdown()

    def _shutdown(self) -> None:
        client = getattr(self, "client", None)
        if client is not None:
            client.close()
            self.client = None
        host, self._host = self._host, None
        if host is not None:
            host.close()
        self._dask_log.setLevel(self._dask_log_level)


def _may_start_processes() -> bool:
    """On a worker: whether it may start processes (a daemon process may not)."""
    import multiprocessing

    return not multiprocessing.current_process().daemon


#: Each worker thread's host pool (run_hosted).
_hosts = threading.local()


def run_hosted(
    fn: Callable[..., Any],
    args: tuple[Any, ...],
    isolation: Isolation | None,
    unit_limit: float | None,
    stop: Callable[[], bool],
) -> Any:
    """On a Dask worker: ``fn(*args)`` in a host process of this worker thread's own, which
    is killed and replaced when a unit runs past ``unit_limit`` and keeps ``isolation``.

    ``stop`` (the run's :class:`DaskStopFlag`) is watched meanwhile and passed on to the
    host's pool, so a stopped run ends the task after its current episode, as elsewhere.
    """
    pool: LocalExecutor | None = getattr(_hosts, "pool", None)
    if pool is None:
        pool = _hosts.pool = LocalExecutor(1)
    finished = threading.Event()
    stopped = threading.Event()

    def watch() -> None:
        while not finished.wait(0.2):
            if stop():
                stopped.set()
                pool.request_stop()
                return

    watcher = threading.Thread(target=watch, name="puckboard-dask-stop", daemon=True)
    watcher.start()
    try:
        (value,) = pool.run(fn, [args], isolation=[isolation], unit_limit=unit_limit)
    finally:
        finished.set()
        watcher.join()
        if stopped.is_set():
            pool.cancel()  # the next task starts unstopped, in a fresh host
    return value


def _new_stop_name() -> str:
    """A name no other sweep on the same Dask cluster uses."""
    import uuid

    return f"puckboard-sweep-stop-{uuid.uuid4().hex}"


class _ClusterHost:
    """A Dask ``LocalCluster`` in a child process of its own; see the module docstring."""

    def __init__(self, workers: int, timeout: float) -> None:
        context = worker_context()
        self._conn, child_end = context.Pipe()
        self._process = context.Process(
            target=serve_local_cluster, args=(workers, child_end), name="puckboard-dask-cluster"
        )
        try:
            self._process.start()
            child_end.close()  # so that the host sees end-of-file once we close ours
            deadline = time.monotonic() + timeout
            while not self._conn.poll(0.1):
                if not self._process.is_alive():
                    raise ConnectionError(
                        "the local Dask cluster's process ended "
                        f"(exit code {self._process.exitcode})"
                    )
                if time.monotonic() > deadline:
                    raise TimeoutError(f"no local Dask cluster after {timeout:g} s")
            kind, value = self._conn.recv()
        except BaseException:
            # Ctrl-C while it starts: it closes the cluster once started. Ended outright,
            # it would leave the semaphores of its nannies' queues to multiprocessing's
            # resource tracker, which complains about them on stderr.
            self.close()
            raise
        if kind != "address":
            self.close()
            raise ConnectionError(f"the local Dask cluster did not start: {value}")
        self.address: str = value

    def close(self, wait: float = 10.0) -> None:
        """Ask the host to close its cluster; after ``wait`` seconds, end it outright
        (its workers then end themselves, as Dask workers do when their parent goes)."""
        with contextlib.suppress(OSError):  # it has ended already
            self._conn.send("close")
        self._conn.close()
        self._process.join(wait)
        if self._process.is_alive():
            self._process.terminate()
            self._process.join(5.0)


def serve_local_cluster(workers: int, conn: Any) -> None:
    """Body of the cluster's host process: start the cluster, send its address, serve
    until told to close or until the sweep's process is gone (end-of-file)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # where it was not inherited (Windows)
    import dask
    from dask.distributed import LocalCluster

    dask.config.set({"distributed.worker.daemon": False})  # workers may start hosts
    try:
        cluster = LocalCluster(
            n_workers=workers,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            # the scheduler serves HTTP (health checks) even without a dashboard, by
            # default on port 8787, with a warning on stderr when that is taken
            scheduler_kwargs={"dashboard_address": "127.0.0.1:0"},
            host="127.0.0.1",
            silence_logs=logging.ERROR,
        )
    except Exception as exc:  # reported by the sweep's process, which raises it
        conn.send(("error", f"{type(exc).__name__}: {exc}"))
        return
    try:
        conn.send(("address", cluster.scheduler_address))
        conn.recv()
    except (EOFError, OSError):
        pass
    finally:
        cluster.close()
