"""Knowledge sources: modules that turn blackboard records into derived blackboard records.

In the blackboard architecture (source document §2.1.1) a central store holds everything
that is known, and independent modules -- *knowledge sources* -- tell it which
information they are interested in; when that information arrives they compute and
write what they conclude back to the store. The layered architecture of the same section
names two such levels above the raw sensors: *sensor interpretation* (one sensor:
smooth a noisy IR reading) and *sensor integration* (several sensors together: wheel
encoders plus accelerometer give a pose). Neither level decides anything; the behaviour
layers do that, and they read the derived keys exactly as they read raw sensor keys.

A :class:`KnowledgeSource` declares

* ``reads``: the keys it looks at (relative to a robot's namespace). The first one, or
  ``trigger`` if set, is the key whose *new* records make it compute;
* ``writes``: the keys it produces;
* ``compute(inputs)``: given a consistent :class:`~puckboard.blackboard.Snapshot` of the
  ``reads``, return a dict of the ``writes`` (or ``None`` for "nothing new").

Everything it writes carries the *stamp of the trigger record*: a pose derived from the
encoders read at t = 3.20 s describes t = 3.20 s, however late it was computed. A layer
can then tell how old a derived value is in the same way as a raw one.

Ten lines make one::

    class ForwardSpeed(KnowledgeSource):
        '''Ground speed (m/s) from the measured wheel speeds.'''

        reads = ("wheel_speeds",)
        writes = ("estimate/speed",)

        def compute(self, inputs):
            ws = inputs.value("wheel_speeds")
            return {"estimate/speed": 0.0205 * (ws.left + ws.right) / 2}

A source runs in one of two ways:

* **in the control loop** -- ``source.attach(loop)``: the loop calls it after sensing and
  before the controllers tick (:meth:`ControlLoop.add_before_tick`), so the layers of
  the same tick already see the derived keys. Deterministic: the right choice in a
  simulator. ``ForwardSpeed.for_each_robot(loop)`` attaches one instance per robot,
  since each robot needs its own state;
* **on its own thread** -- ``source.start()``: the thread blocks in
  :meth:`Blackboard.wait_for` on the trigger key and computes as soon as a new record
  arrives (the blackboard's "returned when another module inserts this data"). The
  right choice on a real robot whose sensing thread writes at its own pace, or for a
  slow computation that must not hold up the control cycle. A thread that falls
  behind skips records rather than queueing them, so compute from the newest values
  (cumulative encoder angles, not per-record increments you cannot afford to lose).

A failing ``compute`` is reported, never fatal: the exception is logged (in full the
first time), counted in :attr:`KnowledgeSource.failures` and kept in
:attr:`KnowledgeSource.last_error`, and the derived keys simply are not updated -- a
layer reading them sees them go stale, as it would if a sensor stopped. A bad
estimator must not stop the robot's reflexes. Pass ``strict=True`` to make errors
propagate instead (useful in tests).

This module imports only the blackboard (and names the adapter contract as a type, for
:meth:`KnowledgeSource.configure`): knowledge sources read and write keys, and know no
simulator and no particular backend.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any, ClassVar, Protocol, TypeVar

from ..blackboard import Blackboard, Namespace, Record, Snapshot

if TYPE_CHECKING:
    from ..backends.base import RobotAdapter

__all__ = ["KnowledgeSource"]

log = logging.getLogger(__name__)

S = TypeVar("S", bound="KnowledgeSource")


class _LoopLike(Protocol):
    """What :meth:`KnowledgeSource.attach` needs of a control loop (duck-typed)."""

    bindings: list[Any]

    def add_before_tick(self, callback: Callable[[Any], None]) -> None: ...


class _CarriesLoop(Protocol):
    """An episode, which carries its control loop."""

    @property
    def loop(self) -> _LoopLike: ...


class KnowledgeSource:
    """A blackboard module that derives keys from keys; see the module docstring.

    Subclasses set ``reads`` and ``writes`` and implement :meth:`compute`; they may
    override :meth:`reset` to clear their state. ``ns`` binds the source to a robot's
    namespace now (it can also be bound later by :meth:`bind` or :meth:`attach`).
    ``name`` is the writer name on the records it writes (default: the class name).
    """

    #: Keys (relative to the robot's namespace) this source looks at.
    reads: ClassVar[tuple[str, ...]] = ()
    #: Keys (relative to the robot's namespace) this source writes.
    writes: ClassVar[tuple[str, ...]] = ()
    #: The key whose new records trigger a computation; default ``reads[0]``.
    trigger: ClassVar[str | None] = None

    def __init__(
        self,
        ns: Namespace | None = None,
        *,
        name: str | None = None,
        strict: bool = False,
    ) -> None:
        if not self.reads:
            raise TypeError(f"{type(self).__name__} must declare the keys it reads in `reads`")
        if not self.writes:
            raise TypeError(f"{type(self).__name__} must declare the keys it writes in `writes`")
        if self.trigger_key not in self.reads:
            raise TypeError(
                f"{type(self).__name__}.trigger {self.trigger_key!r} must be one of its reads "
                f"{self.reads}"
            )
        self.name = name or type(self).__name__
        self.strict = strict
        self.ns: Namespace | None = None
        #: How many computations raised an exception.
        self.failures = 0
        #: The most recent exception raised by :meth:`compute`, if any.
        self.last_error: BaseException | None = None
        #: How many times :meth:`compute` ran.
        self.computations = 0
        self._last_seq = 0
        self._thread: threading.Thread | None = None
        self._stop = threading.Event()
        if ns is not None:
            self.bind(ns)

    # -- what subclasses write -------------------------------------------------------------
    def compute(self, inputs: Snapshot) -> Mapping[str, Any] | None:
        """Derive the ``writes`` from a consistent snapshot of the ``reads``.

        ``inputs.value(key)`` is the fresh value of a read key, or ``None`` if it is
        missing or stale (a sensor this backend does not have reads as ``None``: handle
        it). ``inputs.record(key)`` gives the record whatever its age. Return a dict
        whose keys are among ``writes``, or ``None`` when there is nothing to write.
        """
        raise NotImplementedError(f"{type(self).__name__} must implement compute(inputs)")

    def reset(self) -> None:
        """Forget any internal state (called by :meth:`bind`). Default: nothing."""

    def configure(self, robot: RobotAdapter) -> None:
        """Called by :meth:`attach` with the robot's adapter before :meth:`bind`, so a
        source can take what it needs of the robot (its ``profile``, say). Default:
        nothing."""

    # -- binding ---------------------------------------------------------------------------
    @property
    def trigger_key(self) -> str:
        return self.trigger if self.trigger is not None else self.reads[0]

    def bind(self: S, ns: Namespace | Blackboard, robot: str | None = None) -> S:
        """Bind to a robot's namespace (or to ``board.namespace(robot)``), declare the
        ``writes`` there (a key declared already keeps its settings) and reset state."""
        if isinstance(ns, Blackboard):
            if robot is None:
                raise ValueError("bind(blackboard) needs the robot's name: bind(board, 'epuck0')")
            ns = ns.namespace(robot)
        self.ns = ns
        # declared before the first write, so a layer's ``reads`` can name a derived key
        # from the first tick on (the controller refuses keys nobody declared or wrote);
        # a key declared already keeps its settings
        known = set(ns.declared_keys())
        for key in self.writes:
            if key not in known:
                ns.declare(key)
        self._last_seq = 0
        self.reset()
        return self

    def _require_ns(self) -> Namespace:
        if self.ns is None:
            raise RuntimeError(
                f"knowledge source {self.name!r} is not bound to a robot; pass ns= when "
                "creating it, or call bind(namespace) or attach(loop) first"
            )
        return self.ns

    # -- running once ----------------------------------------------------------------------
    def step(self) -> list[Record]:
        """Compute once if the trigger key holds a record not seen yet; return what was written.

        This is what the control loop calls each cycle. It never raises for an error in
        :meth:`compute` (unless ``strict``): see the module docstring.
        """
        ns = self._require_ns()
        inputs = ns.snapshot(self.reads)
        trigger = inputs.record(self.trigger_key)
        if trigger is None or trigger.seq <= self._last_seq:
            return []
        self._last_seq = trigger.seq
        return self._run(ns, inputs, trigger)

    def _run(self, ns: Namespace, inputs: Snapshot, trigger: Record) -> list[Record]:
        try:
            self.computations += 1
            out = self.compute(inputs)
            if not out:
                return []
            unknown = set(out) - set(self.writes)
            if unknown:
                raise KeyError(
                    f"{self.name} wrote {sorted(unknown)}, which it does not declare in "
                    f"writes={self.writes}"
                )
            return ns.put_many(out, stamp=trigger.stamp, writer=self.name)
        except Exception as exc:
            self.failures += 1
            self.last_error = exc
            if self.strict:
                raise
            if self.failures == 1:
                log.exception(
                    "knowledge source %s (%s) failed on %s at t=%.3f; its keys %s are not "
                    "updated", self.name, ns.name, trigger.key, trigger.stamp, self.writes,
                )  # fmt: skip
            elif self.failures in (10, 100) or self.failures % 1000 == 0:
                log.warning(
                    "knowledge source %s (%s) has failed %d times; last error: %s",
                    self.name, ns.name, self.failures, exc,
                )  # fmt: skip
            return []

    # -- in the control loop ---------------------------------------------------------------
    def attach(self: S, loop: _LoopLike | _CarriesLoop, robot: str | None = None) -> S:
        """Run this source in ``loop`` (a ``ControlLoop``, or anything with ``.loop``).

        It is called after sensing and before the controllers tick. ``robot`` names the
        robot whose namespace to use; it may be omitted when the source is already bound
        or the loop drives only one robot.
        """
        loop = _the_loop(loop)
        if robot is not None or self.ns is None:
            adapter = _robot(loop, robot)
            self.configure(adapter)
            self.bind(adapter.ns)
        loop.add_before_tick(self._before_tick)
        return self

    def _before_tick(self, loop: _LoopLike) -> None:
        self.step()

    @classmethod
    def for_each_robot(cls: type[S], loop: _LoopLike | _CarriesLoop, **kwargs: Any) -> dict[str, S]:
        """One instance per robot of ``loop`` (``kwargs`` go to the constructor), attached.

        Returns the instances by robot name, e.g. to inspect ``failures`` later.
        """
        loop = _the_loop(loop)
        out: dict[str, S] = {}
        for binding in loop.bindings:
            source = cls(**kwargs)
            source.attach(loop, binding.adapter.name)
            out[binding.adapter.name] = source
        return out

    # -- on its own thread -----------------------------------------------------------------
    def start(self: S, *, poll: float = 0.1) -> S:
        """Run on a daemon thread that wakes on every new record of the trigger key.

        ``poll`` (wall seconds) is how often the thread checks whether it should stop.
        """
        ns = self._require_ns()
        if self._thread is not None and self._thread.is_alive():
            raise RuntimeError(f"knowledge source {self.name!r} is already running on a thread")
        self._stop.clear()
        self._thread = threading.Thread(
            target=self._thread_main, args=(ns, poll), name=f"{ns.name}-{self.name}", daemon=True
        )
        self._thread.start()
        return self

    def _thread_main(self, ns: Namespace, poll: float) -> None:
        while not self._stop.is_set():
            try:
                ns.wait_for(self.trigger_key, after_seq=self._last_seq, timeout=poll)
            except TimeoutError:
                continue
            self.step()

    def stop(self, timeout: float = 2.0) -> None:
        """Stop the thread started by :meth:`start` (no-op if none is running)."""
        self._stop.set()
        thread, self._thread = self._thread, None
        if thread is not None:
            thread.join(timeout)
            if thread.is_alive():
                log.warning("knowledge source %s did not stop within %.1f s", self.name, timeout)

    @property
    def running(self) -> bool:
        """True while the thread started by :meth:`start` is alive."""
        return self._thread is not None and self._thread.is_alive()

    def __enter__(self: S) -> S:
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()

    def __repr__(self) -> str:
        where = self.ns.name if self.ns is not None else "unbound"
        return f"<{type(self).__name__} {self.name!r} on {where}: {self.reads} -> {self.writes}>"


def _the_loop(loop: _LoopLike | _CarriesLoop) -> _LoopLike:
    """The control loop itself: an Episode carries its loop."""
    inner: Any = getattr(loop, "loop", loop)
    return inner  # type: ignore[no-any-return]


def _robot(loop: _LoopLike, robot: str | None) -> Any:
    adapters = [b.adapter for b in loop.bindings]
    if robot is None:
        if len(adapters) != 1:
            names = ", ".join(a.name for a in adapters)
            raise ValueError(
                f"this loop drives {len(adapters)} robots ({names}); say which one: "
                "attach(loop, robot='name'), or use for_each_robot(loop)"
            )
        return adapters[0]
    for adapter in adapters:
        if adapter.name == robot:
            return adapter
    names = ", ".join(a.name for a in adapters)
    raise ValueError(f"no robot named {robot!r} in this loop; its robots are: {names}")
