"""One table of settings and one registry of variations, read by everything that names one.

A setting's name, unit, bounds and how a scene holds it are said once
(:mod:`puckboard.scenario.settings`); the command line, a sweep's plan, a scene file and
the Python API read them there, so a value is refused in the same words wherever it
comes from. A variation is one entry of :mod:`puckboard.scenario.variation`, so a package
adds one without editing puckboard.
"""

from __future__ import annotations

import ast
import dataclasses
from pathlib import Path

import pytest

import puckboard
from puckboard.cli import main
from puckboard.control.episode import run_episode
from puckboard.errors import SceneError
from puckboard.scenario import load_scene, scene_from_dict
from puckboard.scenario.overrides import apply_scene_overrides
from puckboard.scenario.settings import SETTINGS, check_scene
from puckboard.scenario.variation import (
    VARIATIONS,
    Variation,
    Varied,
    get_variation,
    register_variation,
    variation_names,
)
from puckboard.sweep.plan import PlanError, parse_set

PKG = Path(puckboard.__file__).parent

#: The names a new maintainer would otherwise have to find in many files.
TABLED = (
    "control.period",
    "control.latency",
    "plausible",
    "reality-gap",
    "obstacle.ir_reflectance",
    "surface.line_contrast",
)


def _literals(path: Path) -> set[str]:
    """The strings ``path`` spells as literals, docstrings left out."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    docstrings = {
        id(node.body[0].value)
        for node in ast.walk(tree)
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef))
        and node.body
        and isinstance(node.body[0], ast.Expr)
        and isinstance(node.body[0].value, ast.Constant)
    }
    return {
        node.value
        for node in ast.walk(tree)
        if isinstance(node, ast.Constant) and isinstance(node.value, str)
        and id(node) not in docstrings
    }  # fmt: skip


def test_each_tabled_name_is_spelled_in_its_table_alone():
    spelled: dict[str, list[str]] = {name: [] for name in TABLED}
    for path in PKG.rglob("*.py"):
        for name in set(TABLED) & _literals(path):
            spelled[name].append(str(path.relative_to(PKG)))
    assert spelled == {
        "control.period": ["scenario/settings.py"],
        "control.latency": ["scenario/settings.py"],
        "plausible": ["scenario/variation.py"],
        "reality-gap": ["scenario/variation.py"],
        "obstacle.ir_reflectance": ["scenario/settings.py"],
        "surface.line_contrast": ["scenario/settings.py"],
    }


@pytest.mark.parametrize(
    ("name", "value", "said"),
    [
        ("noise.wheel_speed", 2, "noise.wheel_speed = 2: outside [0, 1] (relative σ"),
        ("control.latency", 1e9, "control.latency = 1e+09: outside [0, 1] s (the loop's delay"),
        ("dt", 0, "dt = 0: outside (0, 1] s (simulation step)"),
    ],
)
def test_a_value_is_bounded_in_the_same_words_wherever_it_is_read(name, value, said):
    with pytest.raises(ValueError) as overrides:
        apply_scene_overrides(load_scene("line-follow"), {name: value})
    with pytest.raises(PlanError) as sweep:
        parse_set(f"{name}={value}")
    assert str(overrides.value).startswith(f"override {said}")
    assert str(sweep.value).startswith(f"parameter {said}")
    scene = apply_scene_overrides(load_scene("line-follow"), {})
    group, field = SETTINGS[name].group, SETTINGS[name].field
    if group == "noise":
        scene = dataclasses.replace(scene, noise=dataclasses.replace(scene.noise, **{field: value}))
    elif group == "control":
        scene = dataclasses.replace(
            scene, control=dataclasses.replace(scene.control, **{field: value})
        )
    else:
        scene = dataclasses.replace(scene, **{field: value})
    with pytest.raises(ValueError) as built:
        check_scene(scene)  # a scene built in Python, before an episode builds its world
    assert str(built.value).startswith(f"scene 'line-follow': {said}")


def test_a_scene_files_bounds_are_the_settings_bounds():
    data = {"robots": [{"name": "r", "x": 0, "y": 0, "theta": 0}], "control": {"latency": 2}}
    with pytest.raises(SceneError, match=r"control\.latency: expected a number <= 1 \(s\)"):
        scene_from_dict(data, source="s.toml")


def test_a_latency_of_1e9_is_one_line_on_the_command_line(capsys):
    """It once ran on at 12.9 GB; now nothing is built."""
    assert main(["run", "two-robot-pass", "--duration", "3", "--set", "control.latency=1e9"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        "puckboard run: error: override control.latency = 1e+09: outside [0, 1] s (the loop's "
        "delay from sensing to the wheels turning, in whole steps of dt; no e-puck's link is "
        "slower than a second); give a value in that interval"
    ]


def test_a_setting_reads_its_value_off_a_scene():
    scene = load_scene("two-robot-pass")
    assert SETTINGS["control.period"].read(scene) == scene.dt
    assert SETTINGS["surface.line_contrast"].read(scene) == 1.0
    assert SETTINGS["surface.line_contrast"].read(load_scene("arena")) is None
    assert SETTINGS["obstacle.ir_reflectance"].read(load_scene("line-follow")) is None


def _worn(scene, seed, fixed):
    """Every robot's wheels worn down 0.3 mm: a third party's variation."""
    return Varied(apply_scene_overrides(scene, {"profile.wheel_radius": 0.0202}))


@pytest.fixture
def worn():
    variation = Variation("worn-wheels", "wheels worn 0.3 mm", _worn)
    register_variation(variation)
    yield variation
    del VARIATIONS["worn-wheels"]


def test_a_variation_is_one_entry_that_every_command_takes(worn, capsys):
    assert "worn-wheels" in variation_names()
    result = run_episode("line-follow", controller="stock", variation="worn-wheels", duration=0.5)
    plain = run_episode("line-follow", controller="stock", duration=0.5)
    assert result.robots[0].distance_m != plain.robots[0].distance_m
    assert parse_set("variation=none,worn-wheels")[1] == ("none", "worn-wheels")
    args = ["run", "line-follow", "--controller", "stock", "--duration", "0.5", "--json"]
    assert main([*args, "--variation", "worn-wheels"]) == 0
    assert '"distance_m"' in capsys.readouterr().out


def test_an_installed_package_adds_a_variation_by_entry_point(monkeypatch):
    import importlib.metadata

    from puckboard.scenario import variation as registry

    class EntryPoint:
        name, value, dist = "worn-wheels", f"{__name__}:WORN", None

    monkeypatch.setattr(registry, "_installed_read", False)
    monkeypatch.setattr(importlib.metadata, "entry_points", lambda group: [EntryPoint()])
    monkeypatch.setitem(globals(), "WORN", Variation("worn-wheels", "worn", _worn))
    try:
        assert get_variation("worn-wheels").help == "worn"
    finally:
        VARIATIONS.pop("worn-wheels", None)


def test_a_built_in_variation_cannot_be_replaced():
    with pytest.raises(ValueError, match="variation 'plausible' is built in"):
        register_variation(Variation("plausible", "mine", _worn))
