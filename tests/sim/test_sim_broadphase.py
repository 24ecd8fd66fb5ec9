"""The broad phases that keep the simulator's cost per robot flat give the brute-force
answers: the pairs they find cover every close pair, and the IR sensors and contacts
computed through them equal those computed by visiting every robot and every pair."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import puckboard.sim.broadphase as broadphase_module
from puckboard.bench.scale import swarm_with
from puckboard.scenario.scene import RobotSpec
from puckboard.sim.broadphase import DENSE_MAX, close_pairs
from puckboard.sim.world import World

coordinate = st.floats(min_value=-1.0, max_value=1.0, allow_nan=False, width=64)


@settings(max_examples=200, deadline=None)
@given(
    points=st.lists(st.tuples(coordinate, coordinate), min_size=0, max_size=120),
    reach=st.floats(min_value=0.0, max_value=0.6),
)
def test_close_pairs_cover_every_pair_closer_than_reach(points, reach):
    x = np.array([p[0] for p in points], dtype=float)
    y = np.array([p[1] for p in points], dtype=float)
    i, j = close_pairs(x, y, reach)
    found = list(zip(i.tolist(), j.tolist()))
    assert found == sorted(set(found)), "pairs are unique and sorted by (i, j)"
    assert all(a < b for a, b in found)
    brute = {
        (a, b)
        for a in range(len(points))
        for b in range(a + 1, len(points))
        if math.hypot(x[a] - x[b], y[a] - y[b]) < reach
    }
    assert brute <= set(found)
    # and nothing much farther than reach (the widening is a hair)
    for a, b in found:
        assert math.hypot(x[a] - x[b], y[a] - y[b]) <= reach * (1 + 1e-6) + 1e-9


def test_the_sweep_and_the_dense_test_find_the_same_pairs():
    rng = np.random.default_rng(4)
    for n in (DENSE_MAX + 1, 80, 200):
        x, y = rng.uniform(-1, 1, n), rng.uniform(-0.8, 0.8, n)
        i, j = close_pairs(x, y, 0.15)
        brute = [
            (a, b)
            for a in range(n)
            for b in range(a + 1, n)
            if (x[a] - x[b]) ** 2 + (y[a] - y[b]) ** 2 < 0.15**2
        ]
        assert set(brute) <= set(zip(i.tolist(), j.tolist()))


def _random_swarm(n: int, seed: int):
    """The swarm arena with ``n`` robots at random poses (some overlapping each other)."""
    rng = np.random.default_rng(seed)
    base = swarm_with(n)
    robots = tuple(
        RobotSpec(
            r.name,
            float(rng.uniform(-0.95, 0.95)),
            float(rng.uniform(-0.75, 0.75)),
            float(rng.uniform(-math.pi, math.pi)),
            profile=r.profile,
        )
        for r in base.robots
    )
    return dataclasses.replace(base, robots=robots)


def _mixed_swarm(n: int, seed: int):
    """As :func:`_random_swarm`, every other robot with V-REP's cone sensors: the broad
    phase then serves both sensor models at once."""
    scene = _random_swarm(n, seed)
    robots = tuple(
        dataclasses.replace(r, profile="epuck-vrep") if k % 2 else r
        for k, r in enumerate(scene.robots)
    )
    return dataclasses.replace(scene, robots=robots)


def _as_sets(candidates):
    return {i: (set(circles), set(segments)) for i, (circles, segments) in candidates.items()}


def _random_poses(rng, n):
    return [
        [float(rng.uniform(-0.95, 0.95)), float(rng.uniform(-0.75, 0.75)), 0.0] for _ in range(n)
    ]


@pytest.mark.parametrize("swarm", [_random_swarm, _mixed_swarm])
@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("n", [12, 30, 50])
def test_vectorised_sensor_broad_phase_equals_the_python_one(seed, n, swarm, monkeypatch):
    world = World(swarm(n, seed), seed=seed)
    rng = np.random.default_rng(seed)
    # the broad phase of each IR model the swarm uses: the rays', the cones'
    ir = world.sensing.ir
    phases = [ir["rays"].proximity.broad_phase] + (
        [ir["cone"].cones.broad_phase] if "cone" in ir else []
    )
    for _ in range(5):
        poses = _random_poses(rng, n)
        for broad in phases:
            near, circles_of, segments_of = broad.lists(poses)
            assert set(near) <= set(broad.seers), "only the model's own robots see"
            got, rows, cols, seg_hit = broad.arrays(np.array(poses)[:, :2])
            assert got.tolist() == near
            circles: list[set[int]] = [set() for _ in near]
            for row, c in zip(rows.tolist(), cols.tolist()):
                circles[row].add(c)
            assert circles == [set(circles_of[i]) for i in near]
            assert [set(np.flatnonzero(h).tolist()) for h in seg_hit] == [
                set(segments_of[i]) for i in near
            ]
            # and the per-robot tuples the cones read, through either answer
            answers = []
            for limit in (0, 1000):  # vectorised, then plain Python
                monkeypatch.setattr(broadphase_module, "PYTHON_BROAD_PHASE_MAX", limit)
                answers.append(broad.candidates(poses))
            assert list(answers[0]) == list(answers[1]) == near
            assert _as_sets(answers[0]) == _as_sets(answers[1])


@pytest.mark.parametrize("swarm", [_random_swarm, _mixed_swarm])
@pytest.mark.parametrize("seed", range(2))
@pytest.mark.parametrize("n", [30, 50])
def test_the_rays_cast_from_arrays_holds_the_python_candidates(seed, n, swarm):
    world = World(swarm(n, seed), seed=seed)
    sensors = world.sensing.ir["rays"].proximity
    rng = np.random.default_rng(seed)
    for _ in range(5):
        poses = _random_poses(rng, n)
        robots, circles_of, segments_of = sensors.broad_phase.lists(poses)
        cast = sensors._cast_numpy(np.array(poses)[:, :2])
        if cast is None:
            assert robots == []
            continue
        assert list(cast.robot_list) == robots
        got_circles: list[set[int]] = [set() for _ in robots]
        if cast.circle_rows is not None:
            for row, c in zip(cast.circle_rows.tolist(), cast.circle_index.tolist()):
                got_circles[row].add(c)
        assert got_circles == [set(circles_of[i]) for i in robots]
        # segments: the cast holds their data; map it back to the segments' indices
        index_of = {tuple(row): k for k, row in enumerate(sensors._segments.tolist())}
        got_segments: list[set[int]] = [set() for _ in robots]
        if cast.seg_rows is not None:
            data = np.hstack([cast.seg_ax, cast.seg_ay, cast.seg_ex, cast.seg_ey]).tolist()
            for row, segment in zip(cast.seg_rows.tolist(), data):
                got_segments[row].add(index_of[tuple(segment)])
        assert got_segments == [set(segments_of[i]) for i in robots]


@pytest.mark.parametrize("swarm", [_random_swarm, _mixed_swarm])
@pytest.mark.parametrize("n", [12, 30])
def test_readings_do_not_depend_on_which_broad_phase_ran(n, swarm, monkeypatch):
    scene = swarm(n, 7)
    results = []
    for limit in (0, 1000):  # vectorised, then plain Python
        monkeypatch.setattr(broadphase_module, "PYTHON_BROAD_PHASE_MAX", limit)
        world = World(scene, seed=2)
        for i in range(n):
            world.set_wheel_speeds(i, 4.0 + 0.1 * i, 5.0 - 0.1 * i)
        world.step(40)
        results.append((world.prox_distance.copy(), world.prox_raw.copy(), world.poses.copy()))
    for a, b in zip(results[0], results[1]):
        assert np.array_equal(a, b)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 10_000), n=st.integers(13, 55), spread=st.floats(0.05, 0.9))
def test_contacts_through_the_broad_phase_equal_the_plain_loops(seed, n, spread):
    world = World(_random_swarm(n, 0), seed=0)
    statics = world.statics
    rng = np.random.default_rng(seed)
    # crowded: many robots overlapping each other, the walls and the obstacles
    start = [
        [float(rng.uniform(-spread, spread)), float(rng.uniform(-spread, spread)), 0.0]
        for _ in range(n)
    ]
    plain = [list(p) for p in start]
    broad = [list(p) for p in start]
    radii = [p.body_radius for p in world.profiles]
    assert statics._resolve_plain(plain, radii) == statics._resolve_broad(broad, radii)
    assert plain == broad


@pytest.mark.parametrize("n", [2, 12, 30])
def test_cones_through_the_broad_phase_equal_cones_against_everything(n):
    scene = _random_swarm(n, 3).with_profile("epuck-vrep")
    world = World(scene, seed=1)
    rng = np.random.default_rng(n)
    for _ in range(10):
        poses = [
            [
                float(rng.uniform(-0.95, 0.95)),
                float(rng.uniform(-0.75, 0.75)),
                float(rng.uniform(-math.pi, math.pi)),
            ]
            for _ in range(n)
        ]
        distance, raw = np.zeros((n, 8)), np.zeros((n, 8))
        world.sensing.ir["cone"].cones.sense(poses, distance, raw)
        every_distance, every_raw = np.zeros((n, 8)), np.zeros((n, 8))
        world.sensing.ir["cone"].cones.sense(poses, every_distance, every_raw, every_object=True)
        assert np.array_equal(distance, every_distance)
        assert np.array_equal(raw, every_raw)
