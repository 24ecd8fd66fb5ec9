"""The blackboard: records, namespaces, schemas, staleness, subscriptions, threads."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from puckboard.blackboard import (
    ArraySchema,
    Blackboard,
    InstanceOf,
    MissingValueError,
    NumberSchema,
    StaleValueError,
)
from puckboard.records import Proximity


class ManualClock:
    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


def test_put_get_returns_immutable_record_with_metadata():
    clock = ManualClock()
    bb = Blackboard(clock=clock)
    clock.t = 1.5
    rec = bb.put("r/x", 3, writer="me")
    assert (rec.key, rec.value, rec.stamp, rec.seq, rec.writer) == ("r/x", 3, 1.5, 1, "me")
    assert bb.get("r/x") is rec
    assert bb.put("r/x", 4).seq == 2
    with pytest.raises(AttributeError):
        rec.value = 5  # type: ignore[misc]


def test_missing_key_raises_clear_error():
    bb = Blackboard()
    with pytest.raises(MissingValueError, match="no value has been written"):
        bb.get("nobody/wrote/this")


def test_namespaces_keep_robots_apart():
    bb = Blackboard()
    a, b = bb.namespace("a"), bb.namespace("b")
    a.put("speed", 1.0)
    b.put("speed", 2.0)
    assert a.value("speed") == 1.0
    assert b.value("speed") == 2.0
    assert bb.keys() == ["a/speed", "b/speed"]
    assert a.keys() == ["speed"]


def test_schema_refuses_wrong_shape_naming_the_key():
    bb = Blackboard()
    ns = bb.namespace("epuck0")
    ns.declare("proximity", schema=InstanceOf(Proximity))
    with pytest.raises(ValueError, match=r"epuck0/proximity.*Proximity.*shape \(7,\)"):
        ns.put("proximity", np.zeros(7))
    bb.declare("r/prox", schema=ArraySchema((8,), low=0.0, high=0.05))
    with pytest.raises(ValueError, match=r"r/prox.*shape \(8,\).*got shape \(7,\)"):
        bb.put("r/prox", np.zeros(7))
    with pytest.raises(ValueError, match="r/prox.*finite"):
        bb.put("r/prox", np.full(8, np.nan))
    bb.declare("r/speed", schema=NumberSchema(-1, 1))
    with pytest.raises(ValueError, match="r/speed"):
        bb.put("r/speed", float("nan"))
    with pytest.raises(ValueError, match="r/speed"):
        bb.put("r/speed", 2.0)
    assert bb.put("r/speed", 0.5).value == 0.5


def test_put_many_is_all_or_nothing_when_one_value_is_bad():
    bb = Blackboard()
    bb.declare("r/n", schema=NumberSchema())
    with pytest.raises(ValueError, match="r/n"):
        bb.put_many({"r/ok": 1, "r/n": "not a number"})
    assert bb.keys() == []


def test_bad_keys_are_refused():
    bb = Blackboard()
    for key in ("", "/abs", "trailing/"):
        with pytest.raises(ValueError, match="blackboard keys"):
            bb.put(key, 1)


def test_staleness_is_explicit():
    clock = ManualClock()
    bb = Blackboard(clock=clock)
    bb.declare("r/ground", max_age=0.1)
    bb.put("r/ground", "g")
    snap = bb.snapshot(["r/ground", "r/none"])
    assert snap.status("r/ground") == "fresh"
    assert snap.status("r/none") == "missing"
    assert snap["r/ground"].value == "g"
    clock.t = 0.5
    snap = bb.snapshot(["r/ground"])
    assert snap.status("r/ground") == "stale"
    assert snap.get("r/ground") is None
    assert snap.record("r/ground").value == "g"
    with pytest.raises(StaleValueError, match=r"r/ground.*stale.*0\.500 s old"):
        snap["r/ground"]
    with pytest.raises(StaleValueError):
        bb.value("r/ground")


def test_history_keeps_newest_and_drops_oldest():
    bb = Blackboard()
    bb.declare("r/x", history=3)
    for i in range(10):
        bb.put("r/x", i)
    assert [r.value for r in bb.history("r/x")] == [7, 8, 9]
    assert bb.history("r/other") == ()


def test_subscribers_run_outside_the_lock_and_a_failing_one_is_contained(caplog):
    bb = Blackboard()
    seen = []

    def reads_back(rec):
        # would deadlock if called with the lock held
        seen.append((rec.key, bb.get(rec.key).value))

    def broken(rec):
        raise RuntimeError("boom")

    sub = bb.subscribe("r/*", reads_back)
    bb.subscribe("r/x", broken)
    rec = bb.put("r/x", 1)
    assert rec.value == 1
    assert seen == [("r/x", 1)]
    assert "subscriber" in caplog.text
    assert "boom" in caplog.text
    sub.cancel()
    bb.put("r/x", 2)
    assert seen == [("r/x", 1)]


def test_wait_for_returns_when_another_thread_writes():
    bb = Blackboard()
    bb.put("r/x", 0)
    seq = bb.get("r/x").seq

    def later():
        time.sleep(0.05)
        bb.put("r/x", 42)

    threading.Thread(target=later).start()
    rec = bb.wait_for("r/x", after_seq=seq, timeout=5)
    assert rec.value == 42
    with pytest.raises(TimeoutError, match="r/x"):
        bb.wait_for("r/x", after_seq=rec.seq, timeout=0.05)


def test_hammer_no_lost_update_no_torn_snapshot_no_deadlock():
    """Several writers and readers; each writer writes a pair of keys atomically."""
    bb = Blackboard()
    n_writers, n_writes = 4, 2000
    errors: list[str] = []
    stop = threading.Event()
    counter_lock = threading.Lock()

    def writer(w: int) -> None:
        for i in range(1, n_writes + 1):
            bb.put_many({f"w{w}/a": i, f"w{w}/b": -i}, writer=f"w{w}")
            with counter_lock:  # compound update through the public API
                try:
                    total = bb.get("total").value
                except MissingValueError:
                    total = 0
                bb.put("total", total + 1)

    def reader() -> None:
        keys = [k for w in range(n_writers) for k in (f"w{w}/a", f"w{w}/b")]
        while not stop.is_set():
            snap = bb.snapshot(keys)
            for w in range(n_writers):
                a, b = snap.record(f"w{w}/a"), snap.record(f"w{w}/b")
                if (a is None) != (b is None) or (a is not None and a.value != -b.value):
                    errors.append(f"torn snapshot for w{w}: {a} {b}")

    readers = [threading.Thread(target=reader) for _ in range(3)]
    writers = [threading.Thread(target=writer, args=(w,)) for w in range(n_writers)]
    for t in readers + writers:
        t.start()
    for t in writers:
        t.join(timeout=60)
    stop.set()
    for t in readers:
        t.join(timeout=60)
    assert not any(t.is_alive() for t in readers + writers), "deadlock"
    assert errors == []
    for w in range(n_writers):
        rec = bb.get(f"w{w}/a")
        assert rec.value == n_writes
        assert rec.seq == n_writes  # no lost sequence numbers
    assert bb.get("total").value == n_writers * n_writes
    assert bb.get("total").seq == n_writers * n_writes


def test_written_records_are_ordinary_frozen_records():
    import dataclasses

    from puckboard.blackboard import Record

    bb = Blackboard(clock=lambda: 2.5)
    rec = bb.put("r/x", 7, writer="me")
    same = Record("r/x", 7, 2.5, rec.received, 1, "me")
    assert rec == same and hash(rec) == hash(same) and repr(rec) == repr(same)
    with pytest.raises(dataclasses.FrozenInstanceError):
        rec.value = 8  # type: ignore[misc]
