"""Determinism: one seeded generator per world; sensors and camera never disturb it."""

from __future__ import annotations

import numpy as np
from simworld_helpers import noisy, pass_scene

from puckboard.backends.embedded import EmbeddedAdapter
from puckboard.records import Sensor
from puckboard.scenario.scene import Noise
from puckboard.sim.world import World

ALL = frozenset(Sensor) - {Sensor.LIGHT, Sensor.CAMERA}


def drive(world: World, steps: int = 120, *, look: bool = False) -> np.ndarray:
    """A fixed wheel schedule; returns the pose trace. ``look`` reads every sensor of
    both robots through their adapters and renders their cameras each step."""
    adapters = [EmbeddedAdapter(world, i) for i in range(world.n)] if look else []
    for adapter in adapters:
        adapter.enable(*ALL)
    trace = []
    for k in range(steps):
        world.set_wheel_speeds(0, 3.0 + (k % 7) * 0.3, 3.5)
        world.set_wheel_speeds(1, 4.0, 2.0 + (k % 5) * 0.4)
        world.step()
        for adapter in adapters:
            assert set(adapter.sense_all()) == ALL
            adapter.camera_image()
        if look:
            world.render_camera(1, size=(80, 60))
        trace.append(world.poses.copy())
    return np.array(trace)


def test_same_seed_gives_identical_arrays():
    a = World(pass_scene(noisy()), seed=11)
    b = World(pass_scene(noisy()), seed=11)
    assert np.array_equal(drive(a), drive(b))
    for name in ("prox_raw", "prox_distance", "ground", "encoders", "wheel_speeds"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


def test_different_seeds_differ_when_there_is_noise():
    a = drive(World(pass_scene(noisy()), seed=1))
    b = drive(World(pass_scene(noisy()), seed=2))
    assert not np.array_equal(a, b)


def test_without_noise_the_seed_does_not_matter():
    a = drive(World(pass_scene(), seed=1))
    b = drive(World(pass_scene(), seed=2))
    assert np.array_equal(a, b)


def test_reading_sensors_and_rendering_the_camera_do_not_change_the_run():
    quiet = drive(World(pass_scene(noisy()), seed=5))
    watched = drive(World(pass_scene(noisy()), seed=5), look=True)
    assert np.array_equal(quiet, watched)


def test_start_jitter_is_drawn_once_from_the_seed():
    jitter = Noise(start_jitter=0.01)
    a = World(pass_scene(jitter), seed=3).poses
    b = World(pass_scene(jitter), seed=3).poses
    c = World(pass_scene(jitter), seed=4).poses
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)
    assert np.abs(a[:, :2] - [[0.5, 0.0], [-0.5, 0.0]]).max() < 0.05


def test_the_full_stack_with_a_shipped_scene_is_reproducible():
    from puckboard.backends.embedded import open_embedded
    from puckboard.behaviours import load_controller
    from puckboard.control.loop import ControlLoop

    def run() -> np.ndarray:
        conn = open_embedded("two-robot-pass", seed=7)
        loop = ControlLoop([(a, load_controller("improved")) for a in conn.adapters.values()])
        loop.run(cycles=150)
        return conn.world.poses.copy()

    assert np.array_equal(run(), run())


def test_a_camera_thread_rendering_during_the_run_changes_nothing():
    from puckboard.backends.embedded import open_embedded
    from puckboard.behaviours import load_controller
    from puckboard.control.loop import ControlLoop

    def run(camera_thread: bool) -> np.ndarray:
        conn = open_embedded(pass_scene(noisy()), seed=9)
        frames = []
        if camera_thread:
            adapter = conn.adapters["a"]
            adapter.add_camera_observer(lambda _a, image: frames.append(image))
            adapter.start_camera_thread(period=0.001)
        loop = ControlLoop([(a, load_controller("improved")) for a in conn.adapters.values()])
        loop.run(cycles=200)
        if camera_thread:
            assert frames, "the camera thread rendered nothing"
        return conn.world.poses.copy()

    assert np.array_equal(run(False), run(True))
