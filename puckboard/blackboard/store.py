"""The thread-safe blackboard: one lock, immutable records, explicit staleness.

Why not py_trees' own blackboard? It is a process-wide global with no lock: threads lose
updates and introspection crashes while keys are registered. Robot adapters write from
sensing threads while the behaviour tree ticks, so puckboard keeps the thread boundary
here, in one small store:

* every write replaces a whole immutable :class:`Record`, so a reader can never see half
  a value, and one lock makes a multi-key :meth:`Blackboard.snapshot` consistent: the
  values a decision uses all come from one time frame;
* subscribers are called *after* the lock is released, one failing subscriber is logged
  and never breaks the writer;
* a key can declare a maximum age: a snapshot then tells fresh, stale and missing
  values apart instead of silently handing out old data.
"""

from __future__ import annotations

import itertools
import logging
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from .record import Record
from .schema import InstanceOf, Schema, check

__all__ = [
    "Blackboard",
    "MissingValueError",
    "Namespace",
    "Snapshot",
    "StaleValueError",
    "Subscription",
]

log = logging.getLogger(__name__)

Subscriber = Callable[[Record], None]
#: A write as a slot keeps it: (value, stamp, received, seq, writer), a Record's fields
#: after its key.
Entry = tuple[Any, float, float, int, str]


class MissingValueError(KeyError):
    """A key was read that nobody has written yet."""

    def __str__(self) -> str:  # KeyError quotes its argument; we want a sentence
        return str(self.args[0]) if self.args else "missing value"


class StaleValueError(LookupError):
    """A key's newest value is older than the key's declared maximum age."""


@dataclass
class _Slot:
    schema: Schema | None = None
    max_age: float | None = None
    #: the newest write, and its Record once anyone asked for it (see Blackboard)
    entry: Entry | None = None
    record: Record | None = None
    history: deque[Record] | None = None
    seq: int = 0
    #: a value of exactly this type passes ``schema`` (an ``InstanceOf``) without a call
    exact_type: type | None = None


@dataclass(frozen=True)
class Subscription:
    """Handle returned by :meth:`Blackboard.subscribe`; call :meth:`cancel` to stop."""

    pattern: str
    callback: Subscriber
    _board: Blackboard = field(repr=False)
    _id: int = field(repr=False)

    def cancel(self) -> None:
        self._board._unsubscribe(self)


class Snapshot(Mapping[str, Record]):
    """A consistent view of several keys taken under one lock at time ``now``.

    ``snap[key]`` returns the fresh record or raises :class:`MissingValueError` /
    :class:`StaleValueError`; ``snap.get(key)`` returns ``None`` for both;
    ``snap.status(key)`` says which of ``"fresh"``, ``"stale"`` and ``"missing"`` it is.
    ``snap.value(key)`` is the fresh record's value. The writes are held as they were
    made (``entries``, keyed relative to ``prefix``) and each :class:`Record` is made
    when first asked for.
    """

    __slots__ = ("_entries", "_max_age", "_prefix", "_records", "now")

    def __init__(
        self,
        entries: dict[str, Entry | None],
        max_age: dict[str, float | None],
        now: float,
        prefix: str = "",
    ) -> None:
        self._entries = entries
        self._max_age = max_age
        self._prefix = prefix
        self._records: dict[str, Record] | None = None
        self.now = now

    def status(self, key: str) -> str:
        entry = self._entries.get(key)
        if entry is None:
            return "missing"
        limit = self._max_age.get(key)
        if limit is not None and self.now - entry[1] > limit:
            return "stale"
        return "fresh"

    def __getitem__(self, key: str) -> Record:
        status = self.status(key)
        if status == "fresh":
            return self._record(key)
        if status == "missing":
            raise MissingValueError(f"no value has been written to blackboard key {key!r} yet")
        rec = self._record(key)
        raise StaleValueError(
            f"blackboard key {key!r} is stale: its newest value is {self.now - rec.stamp:.3f} s "
            f"old, the key allows {self._max_age[key]} s"
        )

    def get(self, key: str, default: Any = None) -> Any:  # type: ignore[override]
        """The fresh record, or ``default`` when missing or stale."""
        return self._record(key) if self.status(key) == "fresh" else default

    def value(self, key: str, default: Any = None) -> Any:
        """The fresh value, or ``default`` when missing or stale."""
        # layers call this several times per tick: the status test inlined, not re-called
        entry = self._entries.get(key)
        if entry is None:
            return default
        limit = self._max_age.get(key)
        if limit is not None and self.now - entry[1] > limit:
            return default
        return entry[0]

    def record(self, key: str) -> Record | None:
        """The newest record whatever its age (``None`` if missing)."""
        return self._record(key) if self._entries.get(key) is not None else None

    def _record(self, key: str) -> Record:
        """The Record of ``key``'s write (which exists), made once per snapshot."""
        records = self._records
        if records is None:
            records = self._records = {}
        rec = records.get(key)
        if rec is None:
            entry = self._entries[key]
            assert entry is not None
            rec = records[key] = Record(self._prefix + key, *entry)
        return rec

    def __iter__(self):  # type: ignore[no-untyped-def]
        return iter(self._entries)

    def __len__(self) -> int:
        return len(self._entries)

    def __repr__(self) -> str:
        parts = ", ".join(f"{k}: {self.status(k)}" for k in self._entries)
        return f"Snapshot(now={self.now:.3f}, {parts})"


class Blackboard:
    """A thread-safe key/value store of timestamped, immutable records.

    Keys are ``/``-separated paths; :meth:`namespace` gives a view that prefixes every key
    with a robot's name, so two robots in one process never share keys by accident.

    ``clock`` is the time base of stamps and staleness. A simulation passes its
    simulation clock (so staleness means simulated seconds, whatever the speed-up); the
    default is the host's monotonic clock.

    A write keeps its fields as they came (value, stamp, time received, sequence number,
    writer) and the :class:`Record` holding them is made when someone asks for it: a
    robot writes a dozen keys every control cycle and its controller reads two or three
    values, so most records would never be looked at. Whoever asks for one gets the
    same immutable record, whenever they ask.
    """

    def __init__(self, clock: Callable[[], float] = time.monotonic) -> None:
        self.clock = clock
        self._lock = threading.Lock()
        self._changed = threading.Condition(self._lock)
        self._slots: dict[str, _Slot] = {}
        self._subscribers: dict[str, dict[int, Subscriber]] = {}
        self._sub_ids = itertools.count(1)
        self._waiting = 0  # threads blocked in wait_for (guarded by _lock)

    # -- declarations ----------------------------------------------------------------------
    def declare(
        self,
        key: str,
        *,
        schema: Schema | None = None,
        max_age: float | None = None,
        history: int = 0,
    ) -> None:
        """Declare a key's schema, maximum age (s) and history length (newest kept).

        Declaring again replaces the settings and keeps the current value.
        """
        _check_key(key)
        if max_age is not None and max_age <= 0:
            raise ValueError(f"max_age of {key!r} must be positive seconds, got {max_age}")
        if history < 0:
            raise ValueError(f"history of {key!r} must be >= 0, got {history}")
        with self._lock:
            slot = self._slots.setdefault(key, _Slot())
            slot.schema = schema
            slot.exact_type = schema.cls if type(schema) is InstanceOf else None
            slot.max_age = max_age
            if history:
                old = list(slot.history or ())
                slot.history = deque(old[-history:], maxlen=history)
            else:
                slot.history = None

    # -- writing ---------------------------------------------------------------------------
    def put(self, key: str, value: Any, *, stamp: float | None = None, writer: str = "") -> Record:
        """Write one value; returns the record stored. Subscribers run after the lock."""
        return self.put_many({key: value}, stamp=stamp, writer=writer)[0]

    def put_many(
        self, values: Mapping[str, Any], *, stamp: float | None = None, writer: str = ""
    ) -> list[Record]:
        """Write several values atomically: a snapshot sees all of them or none. Returns
        the records stored."""
        return self._write(values, stamp, writer, True)

    def write_many(
        self, values: Mapping[str, Any], *, stamp: float | None = None, writer: str = ""
    ) -> None:
        """:meth:`put_many` for a writer that does not need the records back (a robot's
        sensing cycle, a controller's decision): none is made until someone reads one."""
        self._write(values, stamp, writer, False)

    def _write(
        self, values: Mapping[str, Any], stamp: float | None, writer: str, records: bool
    ) -> list[Record]:
        received = time.monotonic()
        if stamp is None:
            stamp = self.clock()
        written: list[Record] = []
        items = values.items()
        with self._lock:
            slots = self._slots
            pending = []
            for key, value in items:  # validate all before writing any
                slot = slots.get(key)
                if slot is None:
                    _check_key(key)
                elif slot.schema is not None and type(value) is not slot.exact_type:
                    check(key, slot.schema, value)
                pending.append((key, value, slot))
            made = records or bool(self._subscribers)  # records someone is handed now
            for key, value, slot in pending:
                if slot is None:
                    slot = slots[key] = _Slot()
                seq = slot.seq = slot.seq + 1
                entry = slot.entry = (value, stamp, received, seq, writer)
                if made or slot.history is not None:
                    rec = slot.record = Record(key, *entry)
                    if slot.history is not None:
                        slot.history.append(rec)
                    written.append(rec)
                else:
                    slot.record = None
            # waking waiters costs a lock probe even when nobody waits, on every write
            if self._waiting:
                self._changed.notify_all()
            callbacks = self._callbacks_for(written) if self._subscribers else ()
        for callback, rec in callbacks:
            try:
                callback(rec)
            except Exception:
                log.exception("blackboard subscriber %r failed on key %r", callback, rec.key)
        return written

    # -- reading ---------------------------------------------------------------------------
    def get(self, key: str) -> Record:
        """The newest record of ``key`` whatever its age; raises if never written."""
        with self._lock:
            slot = self._slots.get(key)
            rec = _record_of(key, slot) if slot is not None else None
        if rec is None:
            raise MissingValueError(f"no value has been written to blackboard key {key!r} yet")
        return rec

    def value(self, key: str) -> Any:
        """The current value of ``key``; raises if missing or stale."""
        return self.snapshot([key])[key].value

    def snapshot(self, keys: Iterable[str] | None = None, *, prefix: str = "") -> Snapshot:
        """A consistent view of ``keys`` (or of every key under ``prefix``) at one instant."""
        with self._lock:
            now = self.clock()
            if keys is None:
                keys = [k for k in self._slots if k.startswith(prefix)]
            entries: dict[str, Entry | None] = {}
            ages: dict[str, float | None] = {}
            for key in keys:
                slot = self._slots.get(key)
                entries[key] = slot.entry if slot is not None else None
                ages[key] = slot.max_age if slot is not None else None
        return Snapshot(entries, ages, now)

    def history(self, key: str) -> tuple[Record, ...]:
        """The kept history of ``key``, oldest first (empty if none is kept)."""
        with self._lock:
            slot = self._slots.get(key)
            return tuple(slot.history) if slot is not None and slot.history else ()

    def keys(self, prefix: str = "") -> list[str]:
        """Every key that holds a value, sorted."""
        with self._lock:
            return sorted(
                k for k, s in self._slots.items() if s.entry is not None and k.startswith(prefix)
            )

    def declared_keys(self, prefix: str = "") -> list[str]:
        """Every key declared or written, sorted: what a reader may expect to see, where
        :meth:`keys` lists only what holds a value now."""
        with self._lock:
            return sorted(k for k in self._slots if k.startswith(prefix))

    def wait_for(self, key: str, *, after_seq: int = 0, timeout: float | None = None) -> Record:
        """Block until ``key`` holds a record newer than ``after_seq``; return it.

        This is the blackboard architecture's promise: asking for data that is not there
        yet returns once another module writes it. Raises ``TimeoutError`` after
        ``timeout`` seconds (wall clock).
        """
        deadline = None if timeout is None else time.monotonic() + timeout
        with self._lock:
            while True:
                slot = self._slots.get(key)
                rec = _record_of(key, slot) if slot is not None else None
                if rec is not None and rec.seq > after_seq:
                    return rec
                remaining = None if deadline is None else deadline - time.monotonic()
                if remaining is not None and remaining <= 0:
                    raise TimeoutError(
                        f"no value newer than seq {after_seq} arrived at blackboard key "
                        f"{key!r} within {timeout} s"
                    )
                self._waiting += 1
                try:
                    self._changed.wait(remaining)
                finally:
                    self._waiting -= 1

    # -- subscriptions ---------------------------------------------------------------------
    def subscribe(self, pattern: str, callback: Subscriber) -> Subscription:
        """Call ``callback(record)`` after every write to ``pattern``.

        ``pattern`` is a key, or a prefix ending in ``/*`` (``"epuck0/*"``) for every key
        below it, or ``"*"`` for all keys. Callbacks run in the writer's thread, outside
        the lock, so they may read or write the blackboard themselves.
        """
        if not callable(callback):
            raise TypeError(f"subscriber for {pattern!r} must be callable, got {callback!r}")
        sub_id = next(self._sub_ids)
        with self._lock:
            self._subscribers.setdefault(pattern, {})[sub_id] = callback
        return Subscription(pattern, callback, self, sub_id)

    def _unsubscribe(self, sub: Subscription) -> None:
        with self._lock:
            subs = self._subscribers.get(sub.pattern)
            if subs is not None:
                subs.pop(sub._id, None)
                if not subs:
                    del self._subscribers[sub.pattern]

    def _callbacks_for(self, records: list[Record]) -> list[tuple[Subscriber, Record]]:
        out: list[tuple[Subscriber, Record]] = []
        for rec in records:
            for pattern, subs in self._subscribers.items():
                if _matches(pattern, rec.key):
                    out.extend((cb, rec) for cb in subs.values())
        return out

    # -- namespaces ------------------------------------------------------------------------
    def namespace(self, name: str) -> Namespace:
        """A view whose keys are all below ``name/``."""
        return Namespace(self, name)


class Namespace:
    """A blackboard view that prefixes every key with ``name/``.

    Adapters and layers of one robot share one namespace; they never spell the robot's
    name in a key, so the same controller code serves any robot.
    """

    __slots__ = ("board", "name", "prefix")

    def __init__(self, board: Blackboard, name: str) -> None:
        _check_key(name)
        self.board = board
        self.name = name
        self.prefix = name + "/"

    def key(self, key: str) -> str:
        """The absolute key of a relative one."""
        return self.prefix + key

    def declare(self, key: str, **settings: Any) -> None:
        self.board.declare(self.prefix + key, **settings)

    def put(self, key: str, value: Any, *, stamp: float | None = None, writer: str = "") -> Record:
        return self.board.put(self.prefix + key, value, stamp=stamp, writer=writer)

    def put_many(
        self, values: Mapping[str, Any], *, stamp: float | None = None, writer: str = ""
    ) -> list[Record]:
        p = self.prefix
        return self.board.put_many(
            {p + k: v for k, v in values.items()}, stamp=stamp, writer=writer
        )

    def write_many(
        self, values: Mapping[str, Any], *, stamp: float | None = None, writer: str = ""
    ) -> None:
        p = self.prefix
        self.board.write_many({p + k: v for k, v in values.items()}, stamp=stamp, writer=writer)

    def get(self, key: str) -> Record:
        return self.board.get(self.prefix + key)

    def value(self, key: str) -> Any:
        return self.board.value(self.prefix + key)

    def snapshot(self, keys: Iterable[str] | None = None) -> Snapshot:
        """A consistent snapshot; keys in the result are relative to this namespace."""
        p = self.prefix
        if keys is not None:
            # every controller tick takes one: read the slots directly under the board's
            # lock instead of building absolute keys and re-keying a second snapshot
            board = self.board
            entries: dict[str, Entry | None] = {}
            ages: dict[str, float | None] = {}
            with board._lock:
                now = board.clock()
                slots = board._slots
                for key in keys:
                    slot = slots.get(p + key)
                    if slot is None:
                        entries[key] = ages[key] = None
                    else:
                        entries[key] = slot.entry
                        ages[key] = slot.max_age
            return Snapshot(entries, ages, now, p)
        snap = self.board.snapshot(prefix=p)
        n = len(p)
        return Snapshot(
            {k[n:]: e for k, e in snap._entries.items()},
            {k[n:]: a for k, a in snap._max_age.items()},
            snap.now,
            p,
        )

    def history(self, key: str) -> tuple[Record, ...]:
        return self.board.history(self.prefix + key)

    def keys(self) -> list[str]:
        n = len(self.prefix)
        return [k[n:] for k in self.board.keys(self.prefix)]

    def declared_keys(self) -> list[str]:
        n = len(self.prefix)
        return [k[n:] for k in self.board.declared_keys(self.prefix)]

    def wait_for(self, key: str, *, after_seq: int = 0, timeout: float | None = None) -> Record:
        return self.board.wait_for(self.prefix + key, after_seq=after_seq, timeout=timeout)

    def subscribe(self, key: str, callback: Subscriber) -> Subscription:
        """Subscribe to a relative key, or ``"*"`` for every key of this namespace."""
        return self.board.subscribe(self.prefix + key, callback)

    @property
    def clock(self) -> Callable[[], float]:
        return self.board.clock

    def __repr__(self) -> str:
        return f"Namespace({self.name!r})"


def _record_of(key: str, slot: _Slot) -> Record | None:
    """The Record of ``slot``'s newest write, made on first asking (hold the lock)."""
    rec = slot.record
    if rec is None and slot.entry is not None:
        rec = slot.record = Record(key, *slot.entry)
    return rec


def _matches(pattern: str, key: str) -> bool:
    if pattern == key or pattern == "*":
        return True
    return pattern.endswith("/*") and key.startswith(pattern[:-1])


def _check_key(key: str) -> None:
    if not isinstance(key, str) or not key or key.startswith("/") or key.endswith("/"):
        raise ValueError(
            f"blackboard keys are non-empty '/'-separated paths without a leading or trailing "
            f"'/', got {key!r}"
        )
