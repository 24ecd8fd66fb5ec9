"""Worker processes the sweep can stop: each runs tasks for the parent, which may kill it.

A local worker is a *host*: a spawned process that takes tasks (a function and its
arguments) over a pipe and sends back what they return. The parent runs the hosts itself
(:class:`~puckboard.sweep.executors.LocalExecutor`) rather than through a process pool,
because it must be able to do what a pool cannot: end one worker in the middle of a task
and carry on with a new one. That is how an episode's wall-clock limit is enforced on the
process that runs it — a layer blocked in ``time.sleep(3600)`` or in a C call never
returns to Python, so nothing inside the process can stop it, but the parent can kill the
process.

A task may report *units* as it goes (:func:`puckboard.sweep.worker.report_unit_began`,
``report_unit_done``; a batch's units are its episodes), so the parent knows which unit
was running when it killed the host, or when the host died on its own (``os._exit``, a
crash, the memory limit), and which units had already finished. The task is then run
again on a fresh host from that unit on, told why the unit was lost, so that the lost
episode becomes an error row of its kind and every other episode still runs.

An :class:`Isolation` keeps tasks apart: a host serves tasks of one isolation only, for
its whole life (a class's submissions each get processes of their own), in a working
folder of its own, with its output in a file and its memory and file sizes bounded
where the platform allows.

Hosts are spawned (see :mod:`puckboard.sweep.executors`), start with Ctrl-C ignored
(:mod:`puckboard.sweep.signals`) and end themselves when the parent is gone.
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
import sys
import threading
import traceback
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from . import worker

if TYPE_CHECKING:
    from multiprocessing.connection import Connection
    from multiprocessing.context import SpawnContext
    from multiprocessing.synchronize import Event

__all__ = ["Host", "Isolation", "RemoteError", "host_main"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Isolation:
    """Processes of their own for the tasks that carry this value (equal values share).

    ``name`` says whose tasks they are (a submission's version). ``workdir``: the folder
    the process works in, so the files it writes by relative path land there.
    ``output``: a file that takes everything the process prints (its stdout and stderr).
    Give both as absolute paths: the process's working folder is not the parent's.
    ``memory_bytes``: how much memory the process may take beyond what it holds once
    started (enforced where the platform allows: Linux); more raises ``MemoryError``.
    ``file_bytes``: the largest file it may write, its output file included (POSIX).
    """

    name: str
    workdir: str | None = None
    output: str | None = None
    memory_bytes: int | None = None
    file_bytes: int | None = None


class RemoteError(Exception):
    """A task raised in its host and the exception itself could not travel back; the
    message holds its type, text and the host's traceback."""


# -- the host process ----------------------------------------------------------------------
class _Reporter:
    """Sends a running task's unit reports to the parent."""

    def __init__(self, conn: Connection) -> None:
        self.conn = conn
        self.task: int | None = None

    def began(self, index: int) -> None:
        self.conn.send(("began", self.task, index))

    def done(self, index: int, value: Any) -> None:
        self.conn.send(("unit", self.task, index, value))


def host_main(conn: Connection, parent_alive: Connection, stop_event: Event) -> None:
    """Body of a host process: serve tasks from ``conn`` until told to exit or until the
    parent is gone.

    * Ctrl-C is ignored: it reaches every process of the terminal's group, but the parent
      decides what to keep and ends the hosts itself (on POSIX the process was created
      with SIGINT ignored already, see :mod:`puckboard.sweep.signals`).
    * ``parent_alive`` is the reading end of a pipe the parent holds open and never
      writes to: it reports end-of-file once the parent has exited, however it ended
      (SIGKILL included), and the host then exits too.
    * ``stop_event`` is the pool's "stop after this episode" flag
      (:class:`~puckboard.sweep.worker.LocalStopFlag`).
    * What an episode needs is imported now, while the pool starts, not in the first task.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    worker.bind_stop_event(stop_event)

    def exit_with_parent() -> None:
        try:
            while True:
                parent_alive.recv()  # nothing is ever sent: returns only at end-of-file
        except (EOFError, OSError):
            os._exit(1)

    threading.Thread(target=exit_with_parent, name="puckboard-parent-watch", daemon=True).start()
    from ..control import episode  # noqa: F401

    worker.mark_ready()
    reporter = _Reporter(conn)
    worker.set_unit_reporter(reporter)
    while True:
        try:
            message = conn.recv()
        except (EOFError, OSError):
            return
        if message[0] == "exit":
            return
        if message[0] == "isolate":
            _isolate(message[1])
            continue
        _, task, fn, args, kwargs = message
        reporter.task = task
        try:
            value = fn(*args, **kwargs)
        except BaseException as exc:  # the task's own failure: the parent raises it
            _send_failure(conn, task, exc)
            continue
        finally:
            reporter.task = None
        try:
            conn.send(("done", task, value))
        except Exception as exc:  # a value that cannot be pickled
            _send_failure(conn, task, exc)


def _send_failure(conn: Connection, task: int, exc: BaseException) -> None:
    try:
        conn.send(("failed", task, exc))
    except Exception:  # the exception itself cannot travel: its text can
        text = "".join(traceback.format_exception(type(exc), exc, exc.__traceback__))
        conn.send(("failed", task, RemoteError(f"{type(exc).__name__}: {exc}\n{text}")))


def _isolate(isolation: Isolation) -> None:
    """Give this process ``isolation``'s output file, folder and limits."""
    if isolation.output is not None:
        sys.stdout.flush()
        sys.stderr.flush()
        os.makedirs(os.path.dirname(os.path.abspath(isolation.output)), exist_ok=True)
        fd = os.open(isolation.output, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o644)
        os.dup2(fd, 1)
        os.dup2(fd, 2)
        os.close(fd)
    if isolation.workdir is not None:
        os.makedirs(isolation.workdir, exist_ok=True)
        os.chdir(isolation.workdir)
    # what it prints is its own: puckboard's warnings about it are not
    ours = logging.getLogger("puckboard")
    ours.handlers = [logging.NullHandler()]
    ours.propagate = False
    _limit_memory(isolation.memory_bytes)
    _limit_files(isolation.file_bytes)


def _limit_memory(extra: int | None) -> None:
    """Bound the address space at what the process holds now plus ``extra`` bytes
    (Linux: elsewhere the limit is not enforced, or not readable, and is left alone)."""
    if extra is None or not sys.platform.startswith("linux"):
        return
    import resource

    try:
        with open("/proc/self/statm", encoding="ascii") as f:
            pages = int(f.read().split()[0])
        now = pages * os.sysconf("SC_PAGE_SIZE")
        resource.setrlimit(resource.RLIMIT_AS, (now + extra, now + extra))
    except (OSError, ValueError) as exc:
        log.warning("could not limit this process's memory: %s", exc)


def _limit_files(size: int | None) -> None:
    """No file written beyond ``size`` bytes (POSIX): a write past it fails with an
    ``OSError`` instead of the signal that would kill the process."""
    if size is None or os.name != "posix":
        return
    import resource

    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    with contextlib.suppress(OSError, ValueError):
        resource.setrlimit(resource.RLIMIT_FSIZE, (size, size))


# -- the parent's side ---------------------------------------------------------------------
#: A host that has run nothing yet: it may take a task of any isolation.
FRESH = Isolation("(fresh)")


@dataclass(eq=False)
class Task:
    """One task of a run, as the parent follows it across the hosts that run it."""

    number: int
    fn: Any
    args: tuple[Any, ...]
    isolation: Isolation | None
    kwargs: dict[str, Any] = field(default_factory=dict)
    #: unit values of earlier attempts (a unit task run again from a lost unit on)
    prefix: list[Any] = field(default_factory=list)
    #: the unit this attempt started from, and the values it has reported since
    start: int = 0
    units: list[Any] = field(default_factory=list)
    #: the unit running now, and when it must have ended (``time.monotonic()``)
    current: int | None = None
    deadline: float | None = None

    def finished_units(self) -> list[Any]:
        """Every unit value reported so far, in order, over every attempt."""
        return [*self.prefix, *self.units]


class Host:
    """The parent's handle on one host process: its pipe, isolation and current task."""

    def __init__(
        self,
        context: SpawnContext,
        parent_alive: Connection,
        stop_event: Event,
        isolation: Isolation | None = FRESH,
    ) -> None:
        self.conn, child = context.Pipe()
        self.process = context.Process(
            target=host_main,
            args=(child, parent_alive, stop_event),
            name="puckboard-worker",
            daemon=True,  # ended by multiprocessing if this process exits with it running
        )
        self.process.start()
        child.close()  # the host's end: ours is the only other, so its exit is end-of-file
        self.isolation: Isolation | None = FRESH
        self.task: Task | None = None
        if isolation is not FRESH:
            self.isolate(isolation)

    @property
    def sentinel(self) -> int:
        return int(self.process.sentinel)

    def isolate(self, isolation: Isolation | None) -> None:
        """Give a fresh host its isolation (``None``: shared by every untagged task)."""
        if isolation is not None:
            self.conn.send(("isolate", isolation))
        self.isolation = isolation

    def takes(self, isolation: Isolation | None) -> bool:
        return self.isolation is FRESH or self.isolation == isolation

    def assign(self, task: Task) -> None:
        if self.isolation is FRESH:
            self.isolate(task.isolation)
        self.task = task
        task.current = task.deadline = None
        task.units = []
        self.conn.send(("task", task.number, task.fn, task.args, task.kwargs))

    def kill(self) -> None:
        """End the process now (SIGKILL on POSIX) and wait until it has gone."""
        with contextlib.suppress(OSError, ValueError):
            if self.process.is_alive():
                self.process.kill()
            self.process.join(10.0)
        self.conn.close()

    def exit(self, wait: float) -> None:
        """Ask an idle host to exit; kill it if it has not after ``wait`` seconds."""
        with contextlib.suppress(OSError, ValueError):
            self.conn.send(("exit",))
        self.process.join(wait)
        self.kill()

    def exit_description(self) -> str:
        """How the process ended, in words (after it has)."""
        code = self.process.exitcode
        if code is None:
            return "its process is gone"
        if code < 0:
            try:
                name = signal.Signals(-code).name
            except ValueError:
                name = f"signal {-code}"
            extra = " (the system's memory killer, or someone, killed it)" if -code == 9 else ""
            return f"its process was killed by {name}{extra}"
        return f"its process exited with status {code} (os._exit or a crash)"
