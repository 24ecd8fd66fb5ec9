"""Sensor records and robot profiles: named access, validation, unit conversions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from puckboard.profile import EPUCK1, EPUCK2, get_profile
from puckboard.records import (
    PROX_NAMES,
    VREP_ORDER,
    CameraImage,
    Ground,
    Pose,
    Proximity,
    WheelCommand,
)


def test_proximity_named_access_follows_epuck_order():
    d = np.linspace(0.01, 0.05, 8)
    prox = Proximity(d, np.arange(8.0))
    for i, name in enumerate(PROX_NAMES):
        assert getattr(prox, name) == pytest.approx(d[i])
        assert prox.raw_of(name) == i
    assert prox.front_right == pytest.approx(d[0])  # ps0
    assert prox.front_left == pytest.approx(d[7])  # ps7
    with pytest.raises(AttributeError, match="sensor names are"):
        _ = prox.front_centre


def test_vrep_order_maps_sensor1_to_left_side():
    prox = Proximity(np.linspace(0.01, 0.05, 8), np.zeros(8))
    v = prox.vrep()
    assert v[0] == pytest.approx(prox.left)  # ePuck_proxSensor1
    assert v[2] == pytest.approx(prox.front_left)
    assert v[3] == pytest.approx(prox.front_right)
    assert v[5] == pytest.approx(prox.right)
    assert sorted(VREP_ORDER) == list(range(8))


def test_records_refuse_bad_values_with_named_fields():
    with pytest.raises(ValueError, match=r"Proximity.distance needs 8 values.*\(7,\)"):
        Proximity(np.zeros(7), np.zeros(8))
    with pytest.raises(ValueError, match="finite"):
        Proximity(np.full(8, np.nan), np.zeros(8))
    with pytest.raises(ValueError, match=r"\[0, range"):
        Proximity(np.full(8, 0.2), np.zeros(8))
    with pytest.raises(ValueError, match="Ground.value"):
        Ground(np.array([0.1, 2.0, 0.3]), np.zeros(3))
    with pytest.raises(ValueError, match="WheelCommand.left"):
        WheelCommand(float("inf"), 0.0)
    with pytest.raises(ValueError, match="Pose.theta"):
        Pose(0.0, 0.0, float("nan"))
    with pytest.raises(ValueError, match="H×W×3 uint8"):
        CameraImage(np.zeros((4, 4), dtype=np.uint8))


def test_record_arrays_are_read_only_copies():
    src = np.full(8, 0.05)
    prox = Proximity(src, np.zeros(8))
    src[0] = 0.01
    assert prox.front_right == 0.05
    with pytest.raises(ValueError):
        prox.distance[0] = 0.0


def test_ground_dark_threshold():
    g = Ground(np.array([0.2, 0.6, 0.49]), np.zeros(3))
    assert g.dark().tolist() == [True, False, True]
    assert g.centre == pytest.approx(0.6)


def test_unit_conversions_round_trip():
    p = EPUCK2
    assert p.steps_to_rad(1000) == pytest.approx(2 * math.pi)
    assert p.rad_to_steps(p.steps_to_rad(123.0)) == pytest.approx(123.0)
    assert p.m_s_to_rad_s(p.rad_s_to_m_s(3.0)) == pytest.approx(3.0)
    assert EPUCK1.max_wheel_speed == pytest.approx(EPUCK1.steps_to_rad(1000))
    assert EPUCK2.max_wheel_speed == pytest.approx(EPUCK2.steps_to_rad(1100))
    v, w = p.body_velocity(2.0, 2.0)
    assert (v, w) == (pytest.approx(2.0 * p.wheel_radius), 0.0)
    v, w = p.body_velocity(-1.0, 1.0)
    assert v == 0.0
    assert w == pytest.approx(2 * p.wheel_radius / p.axle_length)
    left, right = p.wheel_speeds(*p.body_velocity(0.7, -1.3))
    assert (left, right) == (pytest.approx(0.7), pytest.approx(-1.3))


def test_profiles_by_name():
    assert get_profile("e-puck1") is EPUCK1
    assert get_profile(EPUCK2) is EPUCK2
    with pytest.raises(ValueError, match="known profiles"):
        get_profile("e-puck3")


def test_sensor_poses_are_clockwise_from_front_right():
    headings = [pose.heading for pose in EPUCK2.prox_poses]
    assert headings[0] < 0 < headings[7]  # ps0 right of forward, ps7 left of forward
    assert EPUCK2.prox_poses[2].y < 0 < EPUCK2.prox_poses[5].y  # right, left
    assert [g.y for g in EPUCK2.ground_poses] == sorted(
        (g.y for g in EPUCK2.ground_poses), reverse=True
    )


def test_docs_profiles_table_is_the_code_s_sources_table():
    """Every number of every profile cites its source in docs/profiles.md, in step with the code."""
    from pathlib import Path

    from puckboard.cli.profiles import markdown_table
    from puckboard.profile import PROFILES

    doc = (Path(__file__).resolve().parents[2] / "docs" / "profiles.md").read_text(encoding="utf-8")
    assert markdown_table(list(PROFILES.values())) in doc
    for profile in PROFILES.values():
        for key in ("wheel_radius", "axle_length", "body_radius", "prox_poses", "prox_model"):
            assert profile.sources.get(key), f"{profile.name}: no source for {key}"


def test_vrep_profile_holds_the_decoded_model():
    """The decoded e-puck.ttm numbers, V-REP order mapped onto ps0..ps7."""
    import math

    from puckboard.profile import EPUCK_VREP
    from puckboard.records import VREP_ORDER

    assert EPUCK_VREP.wheel_radius == 0.02118 and EPUCK_VREP.axle_length == 0.054
    looks = [round(math.degrees(EPUCK_VREP.prox_poses[ps].heading)) for ps in VREP_ORDER]
    assert looks == [90, 45, 15, -15, -45, -90, -145, 145]  # ePuck_proxSensor1..8
    sensor4 = EPUCK_VREP.prox_poses[VREP_ORDER[3]]
    assert (sensor4.x, sensor4.y) == (0.0337, -0.0094)
    assert (EPUCK_VREP.prox_min_distance, EPUCK_VREP.prox_max_distance) == (0.0015, 0.0415)
    assert EPUCK_VREP.prox_range == 0.05  # the controllers' no-detection distance stays
    assert [round(q.y * 1000, 1) for q in EPUCK_VREP.ground_poses] == [10.3, 0.7, -10.3]
