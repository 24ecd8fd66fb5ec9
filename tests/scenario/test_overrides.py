"""The override dialect: one way to write NAME=VALUE and one reading of every name, for
``run --set``, ``sweep --set`` and ``run_episode(overrides=...)`` alike."""

from __future__ import annotations

import pytest

from puckboard.behaviours.overrides import layer_target
from puckboard.scenario.overrides import (
    parse_override,
    parse_overrides,
    parse_value,
    profile_target,
)
from puckboard.sweep.plan import PlanError, parse_set


def test_values_become_numbers_bools_or_strings():
    assert parse_value("3") == 3 and isinstance(parse_value("3"), int)
    assert parse_value("0.05") == pytest.approx(0.05)
    assert parse_value("1e-3") == pytest.approx(0.001)
    assert parse_value("True") is True
    assert parse_value("false") is False
    assert parse_value("left") == "left"
    assert parse_value("'3'") == "3"
    assert parse_value(" 31mm ") == "31mm"  # a unit is read by the profile setting's check


@pytest.mark.parametrize("text", ["3", "2.5", "1e-3", "TRUE", "no", "'7'", '"0.5"', "fast"])
def test_run_and_sweep_read_a_value_alike(text):
    """A sweep of one value is the run of that value: the same text, the same setting."""
    name = "layer.LineFollow.speed"
    (swept,) = parse_set(f"{name}={text}")[1]
    ran = parse_overrides([f"{name}={text}"])[name]
    assert swept == ran and type(swept) is type(ran)


def test_an_assignment_is_split_at_its_first_equals_sign():
    assert parse_override(" noise.ground = 0.1 ") == ("noise.ground", 0.1)
    assert parse_override("layer.Cruise.name=a=b") == ("layer.Cruise.name", "a=b")


def test_a_setting_given_twice_is_refused_naming_both_values():
    with pytest.raises(ValueError, match=r"^--set dt given twice \(dt=0.1, then dt=0.05\); give"):
        parse_overrides(["dt=0.1", "dt=0.05"])


@pytest.mark.parametrize("item", ["foo", "=3", " =3"])
def test_an_assignment_without_a_name_says_what_is_expected(item):
    with pytest.raises(ValueError, match=r"^--set .*: expected NAME=VALUE, e\.g\. --set noise"):
        parse_override(item)


@pytest.mark.parametrize(
    ("name", "target"),
    [
        ("profile.prox_radius.side", (None, "prox_radius.side")),
        ("robot.left.profile.ir_gain", ("left", "ir_gain")),
        ("robot.my.bot.profile.body_radius", ("my.bot", "body_radius")),
        ("robot.profile", None),
        ("noise.proximity", None),
        ("layer.LineFollow.speed", None),
    ],
)
def test_profile_overrides_name_every_robot_or_one(name, target):
    assert profile_target(name) == target


def test_layer_overrides_name_a_layer_and_its_parameter():
    assert layer_target("layer.LineFollow.inner_factor") == ("LineFollow", "inner_factor")
    assert layer_target("noise.proximity") is None
    for bad in ("layer.LineFollow", "layer..speed", "layer.A.b.c"):
        with pytest.raises(ValueError, match="must look like layer.<LayerName>.<attribute>"):
            layer_target(bad)


def test_a_sweep_takes_every_layer_name_a_run_takes():
    """A layer name with a hyphen or a digit-led parameter is refused by the layers
    (naming what they have), not as an unknown kind of parameter."""
    assert parse_set("layer.My-Layer.2nd=1")[0] == "layer.My-Layer.2nd"
    with pytest.raises(PlanError, match="unknown parameter 'layer.A.b.c'"):
        parse_set("layer.A.b.c=1")
