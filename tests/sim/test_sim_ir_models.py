"""The IR sensor models by name: one module each, one ``sense`` contract, found by name."""

from __future__ import annotations

import dataclasses
import importlib
import pkgutil
from pathlib import Path

import numpy as np
import pytest

from puckboard.profile import EPUCK
from puckboard.scenario.scenefile import load_scene
from puckboard.sim import ir_models
from puckboard.sim.ir_models import IrModel, ir_model, ir_model_names
from puckboard.sim.world import World


def test_every_module_of_the_package_is_one_model_found_by_its_name():
    folder = Path(ir_models.__file__).parent
    modules = [m.name for m in pkgutil.iter_modules([str(folder)]) if m.name != "registry"]
    declared = [importlib.import_module(f"puckboard.sim.ir_models.{m}").MODEL for m in modules]
    assert all(isinstance(model, IrModel) for model in declared)
    assert sorted(model.name for model in declared) == list(ir_model_names()) == ["cone", "rays"]
    assert ir_model("rays").has_response and not ir_model("cone").has_response


def test_a_profile_naming_no_model_is_refused_when_its_world_is_built():
    scene = load_scene("line-follow").with_profile(dataclasses.replace(EPUCK, prox_model="ray"))
    with pytest.raises(ValueError, match=r"unknown IR sensor model 'ray' .*cone, rays"):
        World(scene)


def test_each_model_writes_only_its_robots_rows_so_the_order_does_not_matter():
    scene = load_scene("two-robot-pass")
    left, right = scene.robots
    mixed = dataclasses.replace(
        scene, robots=(left, dataclasses.replace(right, profile="epuck"))
    )  # a V-REP robot and a physical one
    world = World(mixed, seed=2)
    world.set_pose(0, 0.0, 0.0, 0.0)
    world.set_pose(1, 0.09, 0.0, np.pi)  # face to face, 2 cm apart: both see the other
    poses = world.poses.tolist()
    readings = []
    for order in (list(world.sensing.ir.values()), list(world.sensing.ir.values())[::-1]):
        distance, raw = np.full((2, 8), -1.0), np.full((2, 8), -1.0)
        for model in order:
            model.sense(poses, None, distance, raw)
        readings.append((distance, raw))
    (d1, r1), (d2, r2) = readings
    assert np.array_equal(d1, d2) and np.array_equal(r1, r2)
    assert (d1 >= 0).all()  # every robot's row written, by its own model
    assert (d1[:, 0] < 0.045).all() and np.array_equal(d1, world.prox_distance)
