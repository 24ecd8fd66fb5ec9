"""A layer slower than the control period is named once per robot (issue 30, round 4,
item 10); how the CLI writes the run's real-time factor is tested in tests/cli."""

from __future__ import annotations

import logging
import types

import pytest

import puckboard.control.tick_timing as tick_timing
from puckboard.behaviours import Controller, Layer
from puckboard.behaviours.cruise import Cruise
from puckboard.control.episode import Episode
from puckboard.records import WheelCommand


class Clock:
    """A stand-in for the wall clock that moves only when a layer says it works."""

    def __init__(self) -> None:
        self.now = 0.0

    def perf_counter(self) -> float:
        return self.now


def controller_with_a_slow_layer(clock: Clock) -> Controller:
    class Ponder(Layer):
        def applies(self, frame):  # type: ignore[no-untyped-def]
            clock.now += 0.3  # "takes" 300 ms each tick
            return False

        def command(self, frame):  # type: ignore[no-untyped-def]
            return WheelCommand.stop()

    return Controller([Ponder(), Cruise()], name="pondering")


def test_a_layer_slower_than_the_period_is_named_once_per_robot(monkeypatch, caplog):
    clock = Clock()
    monkeypatch.setattr(tick_timing, "time", types.SimpleNamespace(perf_counter=clock.perf_counter))
    episode = Episode("line-follow", controller=lambda: controller_with_a_slow_layer(clock))
    with caplog.at_level(logging.WARNING, logger="puckboard.control.tick_timing"):
        episode.run(1.0)
    lines = [r.getMessage() for r in caplog.records if r.name == "puckboard.control.tick_timing"]
    assert len(lines) == len(episode.connection.adapters) == 1
    assert "controller 'pondering' took 300 ms, longer than the 50 ms control period" in lines[0]
    assert "its slowest layer, Ponder, takes 300 ms per tick" in lines[0]


def test_timing_the_layers_changes_no_result(monkeypatch):
    plain = Episode("line-follow", seed=3).run(2.0).to_dict()
    seconds = iter(range(10**6))  # a clock that says each tick took a second: every layer timed
    fake = types.SimpleNamespace(perf_counter=lambda: float(next(seconds)))
    monkeypatch.setattr(tick_timing, "time", fake)
    timed = Episode("line-follow", seed=3).run(2.0).to_dict()
    for key in ("wall_s", "realtime_factor"):
        plain.pop(key), timed.pop(key)
    assert timed == plain



def test_timing_leaves_the_layer_objects_alone_and_ends_with_the_tick(monkeypatch, caplog):
    """The layers are timed where the controller calls them: nothing is set on the
    student's objects (their methods are theirs in the timed tick too), and outside the
    timed tick nothing is timed."""
    clock = Clock()
    monkeypatch.setattr(tick_timing, "time", types.SimpleNamespace(perf_counter=clock.perf_counter))
    shadowed: list[set[str]] = []

    class Watched(Layer):
        def applies(self, frame):  # type: ignore[no-untyped-def]
            clock.now += 0.3
            shadowed.append(set(vars(self)) & {"observe", "applies", "command"})
            return False

        def command(self, frame):  # type: ignore[no-untyped-def]
            return WheelCommand.stop()

    controller = Controller([Watched(), Cruise()], name="watched")
    with caplog.at_level(logging.WARNING, logger="puckboard.control.tick_timing"):
        Episode("line-follow", controller=lambda: controller).run(0.5)
    assert "its slowest layer, Watched, takes 300 ms" in caplog.text  # the tick was timed
    assert len(shadowed) > 2 and shadowed == [set()] * len(shadowed)
    assert controller.tree.visitors == []  # the timing visitor went with the timed tick


def test_time_layers_adds_each_layer_s_seconds_and_stops_when_told():
    from puckboard.backends import FakeAdapter
    from puckboard.behaviours.layer import LayerNode

    clock = Clock()

    class Slow(Layer):
        def observe(self, frame):  # type: ignore[no-untyped-def]
            clock.now += 0.1

        def applies(self, frame):  # type: ignore[no-untyped-def]
            clock.now += 0.2
            return False

        def command(self, frame):  # type: ignore[no-untyped-def]
            return WheelCommand.stop()

    robot = FakeAdapter()
    robot.sense_all()
    controller = Controller([Slow(), Cruise()])
    spent: dict[str, float] = {}
    controller.time_layers(spent, clock.perf_counter)
    controller.tick(robot.ns)
    assert spent == pytest.approx({"Slow": 0.3, "Cruise": 0.0})
    controller.time_layers(None)
    controller.tick(robot.ns)
    assert spent == pytest.approx({"Slow": 0.3, "Cruise": 0.0})  # untimed: nothing added
    nodes = [n for n in controller.root.iterate() if isinstance(n, LayerNode)]
    assert all("update" not in vars(n) for n in nodes)
    robot.close()
