"""A link that varies cycle by cycle: each command's latency drawn from a distribution,
commands that never overtake, readings repeated when no packet came; and the per-cycle
models of the real links, against the recordings they cite."""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np
import pytest

from puckboard.backends.embedded import open_embedded
from puckboard.profile.link_cycles import CycleLatency, LinkCycles
from puckboard.profile.links import LINKS
from puckboard.scenario import load_scene
from puckboard.scenario.conversion import scene_from_dict, scene_to_dict
from puckboard.scenario.scene import Control
from puckboard.sim.link_cycles import LinkCycleState
from puckboard.sim.world import World

LINE = load_scene("line-follow")


def test_a_distribution_is_its_quantiles_linear_between_them():
    d = CycleLatency.of_quantiles({"median": 0.01, "p90": 0.03, "max": 0.15})
    assert d.at(0.0) == 0.01  # no min given: never below the smallest measured
    assert d.at(0.5) == 0.01 and d.at(0.9) == pytest.approx(0.03)
    assert d.at(0.95) == pytest.approx(0.09) and d.at(1.0) == 0.15
    assert CycleLatency.uniform(0.002, 0.01).at(0.5) == pytest.approx(0.006)
    with pytest.raises(ValueError, match="never fall"):
        CycleLatency.of_quantiles({"median": 0.02, "p90": 0.01})
    with pytest.raises(ValueError, match="at least two"):
        CycleLatency.of_quantiles({"median": 0.02})


def test_the_wifi_model_is_the_benchmark_s_and_the_recording_s():
    # UNIFR_API_EPUCK results_go_on_wifi_no_image.json (617 steps after start-up) plus a
    # reading's age (0-10 ms); Gsensors.csv: 769 packets in 1500 rows
    cycles = LINKS["epuck2-wifi"].cycles
    assert cycles is not None
    assert cycles.latency.quantile("median") == pytest.approx(0.00927)
    assert cycles.latency.quantile("p90") == pytest.approx(0.03335)
    assert cycles.latency.quantile("max") == pytest.approx(0.14998)
    assert cycles.repeated == (0.0, pytest.approx(1 - 769 / 1500, abs=0.005))
    for name in ("bluetooth-sercom", "usb-sercom"):
        link = LINKS[name]
        assert link.cycles is not None and link.cycles.assumed
        assert link.cycles.latency.at(0.0) == link.latency[0]
        assert link.cycles.latency.at(1.0) == link.latency[1]
    assert LINKS["coppeliasim-sync"].cycles is None  # a simulator's loop does not vary


def test_commands_never_overtake_and_the_wheels_keep_the_last_one():
    # latencies of 0 to 0.2 s at dt 0.05: every command due no earlier than the one before
    control = Control(cycle_latency=CycleLatency.uniform(0.0, 0.2))
    state = LinkCycleState(control, 1, seed=3, dt=0.05)
    for step in range(200):
        state.send(0, step, (float(step), 0.0))
    dues = [due for due, _ in state.pending[0]]
    assert dues == sorted(dues) and dues[-1] <= 199 + 4
    assert len({d - s for s, d in enumerate(dues)}) > 1  # latencies do vary
    arrived = [state.due(0, step) for step in range(205)]
    got = [a[0] for a in arrived if a is not None]
    assert got == sorted(got)  # the newest of those due, never an older one after it


def test_a_world_with_a_varying_link_delays_commands_by_whole_steps():
    # a fixed 0.06 s of latency rounds to one step of 0.05 s
    scene = dataclasses.replace(
        LINE, control=Control(cycle_latency=CycleLatency.uniform(0.06, 0.06))
    )
    world = World(scene, seed=0)
    world.drive(0, 2.0, 2.0)
    world.step()
    assert world.wheel_speeds[0].tolist() == [0.0, 0.0]
    world.drive(0, 2.0, 2.0)
    world.step()
    assert world.wheel_speeds[0].tolist() == [2.0, 2.0]


def test_repeated_readings_leave_the_last_records_and_their_age_grows():
    scene = dataclasses.replace(LINE, control=Control(repeated=0.5))
    connection = open_embedded(scene, seed=1)
    adapter = next(iter(connection.adapters.values()))
    try:
        fresh = []
        for _ in range(10):
            fresh.append(bool(adapter.sense_all()))
            connection.world.step()
        stamp = adapter.ns.snapshot(["ground"])["ground"].stamp
    finally:
        connection.close()
    # the first packet, then one every other cycle (from a drawn phase)
    assert fresh[0] and sum(fresh[1:]) in (4, 5)
    assert all(a or b for a, b in itertools.pairwise(fresh))  # never two repeats in a row
    if not fresh[-1]:
        assert stamp < connection.world.time - 0.05  # the record kept its old stamp


def test_the_default_loop_has_no_per_cycle_state():
    assert World(LINE, seed=0)._cycles is None
    assert not Control().varies and Control(repeated=0.1).varies


def test_a_scene_file_keeps_a_varying_link():
    cycles = LINKS["epuck2-wifi"].cycles
    assert cycles is not None
    control = Control(period=0.1, cycle_latency=cycles.latency, repeated=0.3, link="epuck2-wifi")
    scene = dataclasses.replace(LINE, control=control)
    again = scene_from_dict(scene_to_dict(scene))
    assert again.control == control


def test_repeated_share_follows_how_often_packets_came():
    measured = LinkCycles(CycleLatency.uniform(0.01, 0.01), (0.5, 0.5), ("m",), False, 0.05)
    assert measured.repeated_at(0.025) == pytest.approx(0.5)
    assert measured.repeated_at(0.05) == 0.0
    assert LinkCycles(CycleLatency.uniform(0, 0), (0.2, 0.4), ("s",), True).repeated_at(1) == 0.2


def test_a_draw_is_the_distribution():
    rng = np.random.default_rng(0)
    cycles = LINKS["epuck2-wifi"].cycles
    assert cycles is not None
    draws = np.array([cycles.latency.at(u) for u in rng.random(4000)])
    assert np.median(draws) == pytest.approx(0.00927, rel=0.1)
    assert np.quantile(draws, 0.9) == pytest.approx(0.03335, rel=0.1)
