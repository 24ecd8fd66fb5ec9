"""Ground sensors: dark over the line, light off it, smooth across the edge."""

from __future__ import annotations

import math

import numpy as np
import pytest
from simworld_helpers import empty_scene, loop_track, robot

from puckboard.scenario.scene import Noise, Track
from puckboard.sim.floor import Floor, luminance
from puckboard.sim.world import World

STRAIGHT = Track([[-1.0, 0.0], [1.0, 0.0]], width=0.012, closed=False)


def world_at(y: float, theta: float = 0.0, track: Track = STRAIGHT, **kw) -> World:
    return World(empty_scene(robot("a", 0.0, y, theta), track=track, **kw))


def test_centre_sensor_on_a_narrow_line_is_dark_and_the_sides_light():
    w = world_at(0.0)
    value = w.ground[0]
    floor = luminance(w.scene.floor_colour)
    line = luminance(STRAIGHT.colour)
    assert value.tolist() == pytest.approx([floor, line, floor])
    assert (value < 0.5).tolist() == [False, True, False]
    assert w.ground_raw[0] == pytest.approx(value * 1023)


def test_the_left_sensor_finds_a_line_to_the_robots_left():
    # robot 1 cm to the right of the line (line at y = 0, robot heading +x at y = -0.01)
    w = world_at(-0.01)
    assert w.ground[0].tolist() == pytest.approx(
        [luminance(STRAIGHT.colour), w.floor.floor_brightness, w.floor.floor_brightness]
    )


def test_off_the_line_everything_is_light_close_to_one():
    w = world_at(0.2)
    assert (w.ground[0] > 0.9).all()
    w = World(empty_scene(robot("a")))  # no track at all
    assert (w.ground[0] > 0.9).all()


def test_crossing_the_edge_changes_the_reading_smoothly():
    values = []
    for y in np.arange(-0.012, 0.0005, 0.0005):
        values.append(world_at(y, theta=0.0).ground[0, 1])
    diffs = np.diff(values)
    assert (diffs <= 1e-12).all()  # moving onto the line only darkens the centre sensor
    assert np.abs(diffs).max() < 0.25  # never jumps from light to dark in one half-millimetre
    assert values[0] > 0.9 and values[-1] < 0.1


def test_ground_noise_is_added_and_clipped():
    w = world_at(0.0, noise=Noise(ground=0.05))
    seen = []
    for _ in range(30):
        w.step()
        seen.append(w.ground[0].copy())
    seen = np.array(seen)
    assert seen[:, 1].std() > 0.01
    assert (seen >= 0).all() and (seen <= 1).all()


def sensor_triples_near_the_loop(seed: int, count: int, spread: float):
    """``count`` (centre, 3×2 points) pairs scattered around the 0.4 × 0.25 m loop:
    three ground sensors within a centimetre of a centre ``spread`` off the line."""
    rng = np.random.default_rng(seed)
    for _ in range(count):
        angle = rng.uniform(0, 2 * math.pi)
        centre = (0.4 * math.cos(angle) + rng.normal(0, spread), 0.25 * math.sin(angle))
        yield centre, np.array(centre) + rng.uniform(-0.01, 0.01, size=(3, 2))


def test_nearby_segment_search_gives_the_same_readings_as_testing_every_segment():
    track = loop_track(0.4, 0.25, n=300, width=0.02)
    floor = Floor(empty_scene(track=track))
    for centre, points in sensor_triples_near_the_loop(0, 50, 0.02):
        near = floor.segments_near([centre], 0.0142)
        assert floor.brightness(points, near) == pytest.approx(floor.brightness(points))


@pytest.mark.parametrize("width", [0.002, 0.004, 0.015, 0.03])
def test_fast_brightness_agrees_with_the_footprint_coverage(width):
    track = loop_track(0.4, 0.25, n=200, width=width)
    floor = Floor(empty_scene(track=track))
    rng = np.random.default_rng(1)
    angles = rng.uniform(0, 2 * math.pi, 300)
    points = np.column_stack(
        [0.4 * np.cos(angles) + rng.normal(0, 0.01, 300), 0.25 * np.sin(angles)]
    )
    expected = floor.floor_brightness + floor.coverage(points) * (
        floor.line_brightness - floor.floor_brightness
    )
    assert floor.brightness(points) == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("width", [0.002, 0.015])
def test_brightness_as_floats_is_exactly_the_array_brightness(width):
    # the world reads its ground sensors through brightness_values (plain floats); it
    # must give bit for bit what brightness gives, near the line, on it and far from it
    track = loop_track(0.4, 0.25, n=200, width=width)
    floor = Floor(empty_scene(track=track))
    for centre, xy in sensor_triples_near_the_loop(2, 100, 0.03):
        points = xy[:, 0] + 1j * xy[:, 1]
        near = floor.segments_near([centre], 0.0142)
        assert floor.brightness_values(points, near) == floor.brightness(points, near).tolist()


def test_a_dark_level_reads_black_tape_as_a_real_e_puck2_does():
    # deinemutterschiff/robotique Gsensors.csv: white 955-965, black tape 300-406 (0.30-0.42
    # of white); a sensor of dark level d reads d + (1 - d) x brightness
    from puckboard.profile import apply_overrides, get_profile

    dark = apply_overrides(
        get_profile("epuck"),
        {"ground_dark.left": 0.22, "ground_dark.centre": 0.35, "ground_dark.right": 0.0},
        source="test",
    )
    assert dark.ground_dark == (0.22, 0.35, 0.0)
    w = World(empty_scene(robot("a", profile=dark), track=STRAIGHT))
    floor, line = luminance(w.scene.floor_colour), luminance(STRAIGHT.colour)
    assert w.ground[0].tolist() == pytest.approx([0.22 + 0.78 * floor, 0.35 + 0.65 * line, floor])
    on, off = 0.35 + 0.65 * line, 0.35 + 0.65 * floor
    assert 0.30 <= on / off <= 0.43  # the recording: black over white 0.30-0.42
    # the shipped profile reads black as 0, as Webots and ARGoS do
    assert get_profile("epuck").ground_dark == (0.0, 0.0, 0.0)


def test_plausible_robots_draw_each_ground_sensor_s_dark_level():
    from puckboard.profile import draw, get_profile, uncertainty, variation_rng

    r = uncertainty(get_profile("epuck"))["ground_dark"]
    assert (r.low, r.high) == (0.0, 0.35) and "Gsensors.csv" in r.source
    robots = [draw(get_profile("epuck"), variation_rng(s, 0)).ground_dark for s in range(20)]
    assert all(0.0 <= d <= 0.35 for g in robots for d in g)
    assert len({g[0] for g in robots}) == 20 and robots[0][0] != robots[0][1]
    assert draw(get_profile("epuck-vrep"), variation_rng(0, 0)).ground_dark == (0.0, 0.0, 0.0)
