"""Camera: shape, upright orientation, obstacles ahead in their colours."""

from __future__ import annotations

import math

import numpy as np
from simworld_helpers import empty_scene, robot

from puckboard.scenario.scene import CircleObstacle, Track
from puckboard.sim.camera import BACKGROUND
from puckboard.sim.world import World

RED = (220, 30, 30)


def test_image_has_the_scene_size_and_is_uint8_rgb():
    w = World(empty_scene(robot("a")))
    px = w.render_camera(0)
    assert px.shape == (39, 52, 3) and px.dtype == np.uint8
    assert w.render_camera(0, size=(160, 120)).shape == (120, 160, 3)


def test_upright_floor_at_the_bottom_background_at_the_top():
    w = World(empty_scene(robot("a")))
    px = w.render_camera(0)
    assert (px[-1] == w.scene.floor_colour).all()
    assert (px[0] == BACKGROUND).all()


def test_an_obstacle_straight_ahead_shows_in_the_centre_columns_in_its_colour():
    post = CircleObstacle(0.25, 0.0, 0.03, colour=RED)
    w = World(empty_scene(robot("a"), obstacles=(post,)))
    px = w.render_camera(0)
    h, width = px.shape[:2]
    red = (px == RED).all(axis=2)
    assert red[h // 2, width // 2 - 1 : width // 2 + 1].all()
    assert not red[:, :5].any() and not red[:, -5:].any()
    # nearer means taller
    w.set_pose(0, 0.12, 0.0, 0.0)
    near = (w.render_camera(0) == RED).all(axis=2)
    assert near[:, width // 2].sum() > red[:, width // 2].sum()


def test_an_obstacle_to_the_left_appears_on_the_left_of_the_image():
    ang = math.radians(15)
    post = CircleObstacle(0.3 * math.cos(ang), 0.3 * math.sin(ang), 0.02, colour=RED)
    w = World(empty_scene(robot("a"), obstacles=(post,)))
    red = (w.render_camera(0) == RED).all(axis=2)
    cols = np.nonzero(red.any(axis=0))[0]
    assert len(cols) and cols.max() < red.shape[1] // 2


def test_the_line_ahead_shows_on_the_floor_and_other_robots_in_their_colour():
    track = Track([[-1.0, 0.0], [1.0, 0.0]], width=0.02, closed=False)
    blue = (30, 60, 200)
    scene = empty_scene(robot("a"), robot("b", 0.3, 0.0, math.pi, colour=blue), track=track)
    px = World(scene).render_camera(0)
    h, width = px.shape[:2]
    assert (px[-1, width // 2] == track.colour).all()
    assert (px[-1, 0] == scene.floor_colour).all()
    assert (px[h // 2, width // 2] == blue).all()
