"""Profile paths: naming a number, checking it, setting it, and rebuilding what was set."""

from __future__ import annotations

import dataclasses
import math

import pytest

from puckboard.errors import ProfileError
from puckboard.profile import (
    EPUCK,
    EPUCK_VREP,
    PROFILES,
    apply_overrides,
    check_value,
    draw,
    profile_from_data,
    profile_to_data,
    profile_values,
    variation_rng,
)


def numbers(profile):
    """Everything a simulator reads of a profile (not the record of how it was made)."""
    skip = {"overrides", "sources", "base", "wheel_radius_left", "wheel_radius_right", "extra"}
    out = {f.name: getattr(profile, f.name) for f in dataclasses.fields(profile)}
    out = {k: v for k, v in out.items() if k not in skip}
    out["wheel_radii"] = profile.wheel_radii
    return out


def test_a_set_number_lands_where_its_path_says():
    p = apply_overrides(
        EPUCK,
        {"prox_max_distance": 0.045, "prox_radius.side": "33mm", "ir_gain.right": 0.8},
        source="test",
    )
    assert p.prox_max_distance == 0.045
    right, left = p.prox_poses[2], p.prox_poses[5]
    assert math.hypot(right.x, right.y) == pytest.approx(0.033)
    assert math.hypot(left.x, left.y) == pytest.approx(0.033)
    # moved along its bearing: still beside the robot, not in front of it
    assert math.atan2(left.y, left.x) == pytest.approx(math.pi / 2)
    assert p.prox_poses[0] == EPUCK.prox_poses[0]  # the other sensors stay
    assert p.ir_gain == (1.0, 1.0, 0.8, 1.0, 1.0, 1.0, 1.0, 1.0)
    assert p.name == "epuck" and p.base == "epuck"
    assert p.sources["ir_gain.right"] == "test"
    assert EPUCK.prox_max_distance == 0.05  # the shipped profile is untouched


def test_a_heading_set_on_a_pair_is_the_left_one_s_and_mirrored_on_the_right():
    p = apply_overrides(EPUCK, {"prox_heading.front": "10deg"}, source="test")
    assert p.prox_poses[7].heading == pytest.approx(math.radians(10))  # front_left
    assert p.prox_poses[0].heading == pytest.approx(math.radians(-10))  # front_right


def test_the_wheel_radius_sets_the_nominal_one_and_both_wheels_and_a_wheel_only_itself():
    p = apply_overrides(EPUCK, {"wheel_radius.left": 0.0201}, source="t")
    assert p.wheel_radius == 0.0205 and p.wheel_radii == (0.0201, 0.0205)
    q = apply_overrides(p, {"wheel_radius": 0.0203}, source="t")
    assert q.wheel_radii == (0.0203, 0.0203) and q.wheel_radius == 0.0203
    assert [path for path, _ in q.overrides] == ["wheel_radius"]  # the older change replaced


def test_the_most_specific_path_wins_whatever_the_order():
    one = apply_overrides(EPUCK, {"ir_gain.right": 0.9, "ir_gain": 1.2}, source="t")
    two = apply_overrides(EPUCK, {"ir_gain": 1.2, "ir_gain.right": 0.9}, source="t")
    assert one.ir_gain == two.ir_gain == (1.2, 1.2, 0.9, 1.2, 1.2, 1.2, 1.2, 1.2)
    # a later broad change replaces an earlier narrow one
    later = apply_overrides(one, {"ir_gain.side": 0.7}, source="t")
    assert later.ir_gain[2] == later.ir_gain[5] == 0.7


@pytest.mark.parametrize("profile", list(PROFILES.values()), ids=list(PROFILES))
def test_setting_a_profile_s_own_values_changes_nothing(profile):
    same = apply_overrides(profile, profile_values(profile), source="t")
    assert numbers(same) == numbers(profile)


def test_a_drawn_robot_is_rebuilt_exactly_from_its_reported_values():
    drawn = draw(EPUCK, variation_rng(3, 1))
    again = apply_overrides(EPUCK, profile_values(drawn), source="t")
    assert numbers(again) == numbers(drawn)
    # and from the form scenes and recordings store it in
    assert profile_from_data(profile_to_data(drawn)) == drawn


@pytest.mark.parametrize(
    ("path", "value", "words"),
    [
        ("prox_max_distanse", 0.04, "did you mean prox_max_distance?"),
        ("prox_radius.frnt", 0.03, "did you mean prox_radius.front?"),
        ("prox_radius", 0.03, "unknown profile setting"),
        ("prox_heading.all", 0.1, "groups: front, diagonal, side, rear"),
        ("axle_length.left", 0.05, "unknown profile setting"),
        ("wheel_radius", 20.5, "outside [0.005 m (5 mm), 0.05 m (50 mm)]"),
        ("ir_gain", 0.0, "outside (0, 10]"),
        ("prox_aperture", math.pi, "outside (0, 3.142 rad (180°))"),
        ("prox_heading.side", -0.5, "outside [0, 3.142 rad (180°)]"),
        ("prox_heading.side", "90mm", "unit 'mm' does not fit"),
        ("ir_gain.right", True, "expected a number"),
        ("ir_gain.right", "strong", "expected a number"),
        ("body_radius", float("nan"), "outside"),
        ("prox_max_distance", 0.07, "within prox_range"),
        ("prox_min_distance", 0.06, "short of prox_max_distance"),
    ],
)
def test_every_mistake_is_one_line_naming_path_value_and_what_is_allowed(path, value, words):
    with pytest.raises(ProfileError) as info:
        apply_overrides(EPUCK, {path: value}, source="t")
    message = str(info.value)
    assert words in message, message
    assert path.split(".")[0] in message and len(message.splitlines()) == 1


def test_detection_limits_are_checked_against_the_profile_they_land_on():
    # 41.5 mm: fine for V-REP's model; 1 mm: below the cone's 1.5 mm inner radius
    assert apply_overrides(EPUCK_VREP, {"prox_max_distance": 0.045}, source="t")
    with pytest.raises(ProfileError, match="prox_max_distance = 0.001: outside"):
        apply_overrides(EPUCK_VREP, {"prox_max_distance": 0.001}, source="t")


def test_units_convert_to_si():
    assert check_value("prox_radius.side", "31mm") == 0.031
    assert check_value("prox_radius.side", "3.1cm") == pytest.approx(0.031)
    assert check_value("prox_heading.front", "17deg") == math.radians(17)
    assert check_value("ir_offset.left", -12) == -12.0
