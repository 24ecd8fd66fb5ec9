"""The knowledge-source pattern: in the loop, on a thread, and when it fails."""

from __future__ import annotations

import logging
import time

import pytest

from puckboard.backends.fake import FakeAdapter, FakeClock
from puckboard.behaviours import Controller, Cruise, Frame, Layer
from puckboard.blackboard import Blackboard
from puckboard.control.loop import ControlLoop
from puckboard.estimation.knowledge import KnowledgeSource
from puckboard.records import WheelCommand, WheelEncoders


class MeanWheelAngle(KnowledgeSource):
    reads = ("encoders",)
    writes = ("derived/mean_angle",)

    def compute(self, inputs):
        enc = inputs.value("encoders")
        return {"derived/mean_angle": (enc.left + enc.right) / 2}


class Broken(KnowledgeSource):
    reads = ("encoders",)
    writes = ("derived/broken",)

    def compute(self, inputs):
        raise ZeroDivisionError("deliberately broken")


class SeesDerived(Layer):
    """Records the derived value it saw in each tick, to prove same-tick visibility."""

    reads = ("derived/mean_angle", "encoders")

    def __init__(self) -> None:
        super().__init__()
        self.seen: list[tuple[float | None, float]] = []

    def applies(self, frame: Frame) -> bool:
        enc = frame.value("encoders")
        self.seen.append((frame.value("derived/mean_angle"), (enc.left + enc.right) / 2))
        return False

    def command(self, frame: Frame) -> WheelCommand:
        return WheelCommand.stop()


def _loop(*layers: Layer, names=("epuck",)):
    clock = FakeClock(dt=0.05)
    board = Blackboard(clock=lambda: clock.time)
    bindings = []
    for name in names:
        adapter = FakeAdapter(name, blackboard=board, clock=clock)
        bindings.append((adapter, Controller([*layers, Cruise(2.0)])))
    return ControlLoop(bindings), board


def test_in_loop_source_writes_derived_key_with_input_stamp_before_the_tick():
    spy = SeesDerived()
    loop, board = _loop(spy)
    source = MeanWheelAngle().attach(loop)
    loop.run(cycles=5)
    derived = board.get("epuck/derived/mean_angle")
    encoders = board.get("epuck/encoders")
    assert derived.stamp == encoders.stamp
    assert derived.writer == "MeanWheelAngle"
    assert derived.value == pytest.approx((encoders.value.left + encoders.value.right) / 2)
    assert source.computations == 5
    # the layer of every tick saw the value derived from that same tick's encoders
    assert len(spy.seen) == 5
    for derived_seen, from_encoders in spy.seen:
        assert derived_seen == pytest.approx(from_encoders)
    assert spy.seen[-1][1] > 0


def test_for_each_robot_keeps_one_state_per_robot_and_attach_needs_a_name():
    loop, board = _loop(names=("a", "b"))
    with pytest.raises(ValueError, match="2 robots"):
        MeanWheelAngle().attach(loop)
    with pytest.raises(ValueError, match="no robot named 'c'"):
        MeanWheelAngle().attach(loop, "c")
    sources = MeanWheelAngle.for_each_robot(loop)
    loop.run(cycles=3)
    assert set(sources) == {"a", "b"}
    assert board.get("a/derived/mean_angle").stamp == board.get("a/encoders").stamp
    assert board.get("b/derived/mean_angle").stamp == board.get("b/encoders").stamp


def test_source_computes_only_on_new_trigger_records():
    board = Blackboard(clock=lambda: 0.0)
    ns = board.namespace("r")
    source = MeanWheelAngle(ns)
    assert source.step() == []  # nothing written yet
    ns.put("encoders", WheelEncoders(1.0, 3.0), stamp=1.5)
    (rec,) = source.step()
    assert rec.value == 2.0 and rec.stamp == 1.5
    assert source.step() == []  # same record: nothing to do
    assert source.computations == 1


def test_threaded_source_follows_the_trigger_key():
    board = Blackboard(clock=lambda: 0.0)
    ns = board.namespace("r")
    with MeanWheelAngle(ns).start(poll=0.02) as source:
        assert source.running
        for i in range(1, 4):
            seq_before = ns.get("derived/mean_angle").seq if i > 1 else 0
            ns.put("encoders", WheelEncoders(float(i), float(i)), stamp=10.0 + i)
            rec = ns.wait_for("derived/mean_angle", after_seq=seq_before, timeout=5.0)
            assert rec.stamp == 10.0 + i
            assert rec.value == float(i)
    assert not source.running


def test_failing_source_is_reported_not_fatal(caplog):
    loop, board = _loop()
    broken = Broken().attach(loop)
    good = MeanWheelAngle().attach(loop)
    with caplog.at_level(logging.ERROR, logger="puckboard.estimation.knowledge"):
        loop.run(cycles=4)
    assert broken.failures == 4
    assert isinstance(broken.last_error, ZeroDivisionError)
    assert board.keys("epuck/derived/broken") == []
    assert good.computations == 4  # the other source and the loop carried on
    assert sum("Broken" in r.getMessage() for r in caplog.records) == 1  # logged once in full


def test_strict_source_raises_and_threaded_failure_keeps_thread_alive():
    board = Blackboard(clock=lambda: 0.0)
    ns = board.namespace("r")
    ns.put("encoders", WheelEncoders(0.0, 0.0))
    with pytest.raises(ZeroDivisionError):
        Broken(ns, strict=True).step()
    with Broken(ns).start(poll=0.02) as broken:
        ns.put("encoders", WheelEncoders(1.0, 1.0))
        deadline = time.monotonic() + 5.0
        while broken.failures == 0 and time.monotonic() < deadline:
            time.sleep(0.01)
        assert broken.failures >= 1
        assert broken.running  # the thread survived its module's exception
        failures = broken.failures
        ns.put("encoders", WheelEncoders(2.0, 2.0))
        while broken.failures == failures and time.monotonic() < deadline:
            time.sleep(0.01)
        assert broken.failures > failures  # and keeps computing on new records


def test_declarations_are_checked():
    class NoWrites(KnowledgeSource):
        reads = ("encoders",)

    class BadTrigger(KnowledgeSource):
        reads = ("encoders",)
        writes = ("x",)
        trigger = "proximity"

    class WritesUndeclared(KnowledgeSource):
        reads = ("encoders",)
        writes = ("x",)

        def compute(self, inputs):
            return {"y": 1}

    with pytest.raises(TypeError, match="writes"):
        NoWrites()
    with pytest.raises(TypeError, match="trigger"):
        BadTrigger()
    with pytest.raises(RuntimeError, match="not bound"):
        MeanWheelAngle().step()
    board = Blackboard(clock=lambda: 0.0)
    board.put("r/encoders", WheelEncoders(0.0, 0.0))
    with pytest.raises(KeyError, match="does not declare"):
        WritesUndeclared(board.namespace("r"), strict=True).step()


def test_layer_can_command_from_derived_key():
    class StopAfterAngle(Layer):
        reads = ("derived/mean_angle",)

        def applies(self, frame: Frame) -> bool:
            angle = frame.value("derived/mean_angle")
            return angle is not None and angle > 0.5

        def command(self, frame: Frame) -> WheelCommand:
            return WheelCommand.stop()

    loop, board = _loop(StopAfterAngle())
    MeanWheelAngle().attach(loop)
    loop.run(cycles=20)
    assert board.value("epuck/command/layer") == "StopAfterAngle"
