"""The calibration's parts on their own: the plan, the model it fits against, the fit,
the profile file it writes."""

from __future__ import annotations

import dataclasses
import datetime
import math
import sys

import numpy as np
import pytest
from calibration_helpers import KNOWN_GAINS, KNOWN_OFFSETS, known_profile, wall_robot

from puckboard.calibration import WallModel, calibrated_profile, fit_sensor, make_plan
from puckboard.calibration.fit import SensorFit
from puckboard.calibration.output import AMBIENT_CHANGE, AmbientLight, profile_file_text
from puckboard.ir_response import cutoff_value
from puckboard.profile import EPUCK, EPUCK1, EPUCK_VREP, apply_overrides, load_profile_file
from puckboard.records import PROX_NAMES
from puckboard.scenario.scene import Noise

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

MODEL = WallModel(EPUCK)


# -- the plan ---------------------------------------------------------------------------
def test_the_default_plan_backs_60_mm_in_3_mm_steps_and_presents_every_sensor():
    plan = make_plan(EPUCK)
    assert plan.stops == 21
    assert plan.backs[0] == 0.0 and plan.backs[-1] == pytest.approx(0.06)
    assert np.allclose(np.diff(plan.backs), 0.003)
    assert plan.start_distance == EPUCK.body_radius
    # each sensor straight at the wall: the robot turned by minus the sensor's heading
    for pres in plan.presentations:
        (name,) = pres.sensors
        heading = EPUCK.prox_poses[PROX_NAMES.index(name)].heading
        assert math.cos(pres.heading + heading) == pytest.approx(1.0)
    headings = [p.heading for p in plan.presentations]
    assert headings == sorted(headings) and len(set(headings)) == 8
    assert sorted(p.name for p in plan.presentations) == sorted(PROX_NAMES)
    # speeds are fractions of the profile's limit: an e-puck1's plan is as gentle
    assert plan.turn_speed / EPUCK.max_wheel_speed == pytest.approx(0.3)
    assert make_plan(EPUCK1).turn_speed / EPUCK1.max_wheel_speed == pytest.approx(0.3)


def test_stops_turn_alternately_one_way_and_the_other():
    plan = make_plan(EPUCK)
    even, end_even = plan.targets(0)
    odd, end_odd = plan.targets(1)
    assert [h for h, _ in even] == sorted(h for h, _ in even) and end_even == pytest.approx(
        2 * math.pi
    )
    assert [h for h, _ in odd] == sorted((h for h, _ in odd), reverse=True) and end_odd == 0.0
    assert [p.name for _, p in odd] == [p.name for _, p in reversed(even)]


def test_the_duration_adds_up_the_moves_and_the_readings():
    plan = make_plan(EPUCK, step=0.01, samples=4, sample_period=0.1)
    reading = (1 + plan.stops * 8) * (plan.settle + 4 * 0.1)
    assert plan.duration() > reading
    slower = make_plan(EPUCK, step=0.01, samples=8, sample_period=0.1)
    assert slower.duration() - plan.duration() == pytest.approx((1 + plan.stops * 8) * 0.4)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"distance": 0.0}, "distance must be more than 0 and at most 150 mm, got 0 mm"),
        ({"distance": 0.2}, "distance must be more than 0 and at most 150 mm, got 200 mm"),
        ({"step": 0.0001}, "step must be at least 0.5 mm"),
        ({"step": 0.07}, "step must be at least 0.5 mm and at most the distance (60 mm)"),
        ({"samples": 1}, "samples must be at least 2"),
        ({"sample_period": 0.0}, "sample period must be more than 0"),
        ({"distance": math.nan}, "distance must be"),
    ],
)
def test_a_plan_that_cannot_work_is_one_line(options, message):
    with pytest.raises(ValueError) as caught:
        make_plan(EPUCK, **options)
    assert str(caught.value).startswith(message)


def test_a_cone_profile_has_nothing_to_calibrate():
    with pytest.raises(ValueError, match="exact cones .* no IR response to calibrate"):
        make_plan(EPUCK_VREP)


# -- the model ----------------------------------------------------------------------------
def test_the_model_is_what_the_simulator_computes_for_a_robot_at_a_wall():
    """The wall of the shipped calibration-wall scene, the engine's noise-free readings:
    the model's expected values are the same numbers."""
    connection = wall_robot(None, noise=Noise())
    world = connection.world
    wall_x = world.scene.arena.xmax
    for distance, heading in [(0.037, 0.0), (0.045, 0.3), (0.06, math.pi / 2), (0.05, 2.6)]:
        world.set_pose(0, wall_x - distance, 0.0, heading)
        assert np.allclose(MODEL.expected(distance, heading), world.prox_raw[0], atol=1e-9)


def test_a_sensor_of_gain_g_and_offset_o_reads_g_times_the_model_plus_o():
    """What makes the fit linear: the simulator's calibrated value, noise-free."""
    connection = wall_robot(known_profile(), noise=Noise())
    world = connection.world
    gains = np.array([KNOWN_GAINS[n] for n in PROX_NAMES])
    offsets = np.array([KNOWN_OFFSETS[n] for n in PROX_NAMES])
    for distance, heading in [(0.037, 0.3), (0.05, 1.6), (0.045, 2.6), (0.07, 4.7)]:
        world.set_pose(0, world.scene.arena.xmax - distance, 0.0, heading)
        expected = np.clip(gains * MODEL.expected(distance, heading) + offsets, 0.0, 4095.0)
        assert np.allclose(world.prox_raw[0], expected, atol=1e-9)


def test_the_model_ignores_the_profiles_own_gains():
    model = WallModel(known_profile())
    assert np.allclose(model.expected(0.045, 0.3), MODEL.expected(0.045, 0.3))


def test_detection_ends_where_the_value_falls_to_the_cut_off():
    cutoff = cutoff_value(EPUCK.prox_max_distance)
    end = MODEL.detection_end("right", 1.0, 0.0)
    assert end is not None and 0.045 < end < 0.05  # a few rays read farther than the axis
    assert MODEL.facing("right", end) == pytest.approx(cutoff, rel=0.01)
    weaker = MODEL.detection_end("right", 0.8, 0.0)
    assert weaker is not None and weaker < end
    assert MODEL.detection_end("right", 1.0, cutoff + 1) is None  # always reads something
    assert MODEL.detection_end("right", 0.01, 0.0) == 0.0  # never above the cut-off


# -- the fit ------------------------------------------------------------------------------
def test_fit_sensor_recovers_a_line_and_weighs_by_the_spread():
    e = np.array([0.0, 0.0, 50.0, 200.0, 800.0, 2000.0])
    y = 0.8 * e + 12.0
    g, o, se_g, se_o, rms = fit_sensor(e, y, np.full(6, 3.0), np.full(6, 10))
    assert (g, o) == (pytest.approx(0.8), pytest.approx(12.0))
    assert rms == pytest.approx(0.0, abs=1e-9)
    assert se_g > 0 and se_o > 0  # from the spread, not from a perfect fit
    # a wild reading with a wide spread hardly moves the fit; with a narrow one it does
    wild = y.copy()
    wild[-1] += 300
    g_wide, *_ = fit_sensor(e, wild, np.array([3, 3, 3, 3, 3, 300.0]), np.full(6, 10))
    g_narrow, *_ = fit_sensor(e, wild, np.full(6, 3.0), np.full(6, 10))
    assert abs(g_wide - 0.8) < abs(g_narrow - 0.8) / 10


# -- the profile file ---------------------------------------------------------------------
def _fits(**overrides):
    fits = [
        SensorFit(n, KNOWN_GAINS[n], KNOWN_OFFSETS[n], 0.01, 0.5, 3.2, 20, 0.047)
        for n in PROX_NAMES
    ]
    return [dataclasses.replace(f, **overrides) for f in fits]


def test_the_profile_file_reads_back_as_the_fitted_numbers_with_their_sources(tmp_path):
    when = datetime.date(2026, 11, 24)
    profile = calibrated_profile(EPUCK, _fits(), name="my-epuck", when=when)
    text = profile_file_text(profile, "measured on 2026-11-24 over a test", header=("hello",))
    assert text.startswith('# hello\nbase = "epuck"\nname = "my-epuck"\n')
    path = tmp_path / "my-epuck.toml"
    path.write_text(text, encoding="utf-8")
    back = load_profile_file(path)
    assert back.name == "my-epuck" and back.base == "epuck"
    assert back.ir_gain == tuple(KNOWN_GAINS[n] for n in PROX_NAMES)
    assert back.ir_offset == tuple(KNOWN_OFFSETS[n] for n in PROX_NAMES)
    source = back.sources["ir_gain.right"]
    assert source == back.sources["ir_offset.right"]
    assert source == (
        "puckboard calibrate ir, 2026-11-24: gain 0.750 ± 0.010, offset 20.0 ± 0.5 raw, "
        "residual RMS 3.2 raw over 20 poses; detects a white wall up to 47.0 mm straight ahead"
    )
    data = tomllib.loads(text)
    assert data["source"] == "measured on 2026-11-24 over a test"
    assert "prox_max_distance" not in data["set"]  # see calibration.output


def test_numbers_the_start_profile_set_are_kept_and_its_gains_replaced():
    mine = apply_overrides(
        EPUCK,
        {"body_radius": 0.035, "ir_gain.left": 0.5, "wheel_radius": 0.0203},
        source={"body_radius": "my ruler", "ir_gain.left": "old", "wheel_radius": "rolled"},
    )
    profile = calibrated_profile(mine, _fits(), name="again", when=datetime.date(2026, 1, 2))
    assert profile.body_radius == 0.035 and profile.sources["body_radius"] == "my ruler"
    assert profile.wheel_radius == 0.0203
    assert profile.ir_gain[PROX_NAMES.index("left")] == KNOWN_GAINS["left"]
    text = profile_file_text(profile, "measured")
    assert '"body_radius" = { value = 0.035, source = "my ruler" }' in text


def test_a_detection_end_that_never_comes_is_said():
    profile = calibrated_profile(
        EPUCK, _fits(detection_end=None), name="x", when=datetime.date(2026, 1, 2)
    )
    assert profile.sources["ir_gain.left"].endswith(
        "its offset is above the cut-off: it always reads something"
    )


def test_ambient_light_that_changes_is_a_warning():
    steady = AmbientLight(np.full(8, 3900.0), np.full(8, 3950.0))
    assert steady.changes() == []
    assert steady.describe() == "ambient light: 3900-3950 (0 bright .. 4095 dark), steady"
    high = np.full(8, 3950.0)
    high[2] = 3900.0 + AMBIENT_CHANGE + 1
    changed = AmbientLight(np.full(8, 3900.0), high)
    assert [c[0] for c in changed.changes()] == ["right"]
    assert changed.describe().startswith("warning: ambient light changed during the run (right:")
    assert AmbientLight(None, None).describe() == "ambient light: not reported by this backend"


# -- what the pages say -------------------------------------------------------------------
def test_the_calibration_wall_scene_is_what_its_description_says():
    from puckboard.scenario.scenefile import load_scene, scene_description

    scene = load_scene("calibration-wall")
    (robot,) = scene.robots
    arena = scene.arena
    assert (arena.xmax - arena.xmin, arena.ymax - arena.ymin) == (0.6, 0.6)
    # touching the east wall, facing it
    assert arena.xmax - robot.x == pytest.approx(EPUCK.body_radius)
    assert robot.theta == 0.0 and scene.noise.start_jitter == 0.0
    # "nothing else within 25 cm": the other walls, from the body's edge
    others = (robot.x - arena.xmin, arena.ymax - robot.y, robot.y - arena.ymin)
    assert min(others) - EPUCK.body_radius > 0.25
    assert not scene.obstacles
    assert "nothing else within 25 cm" in scene_description("calibration-wall")


def test_the_real_robot_pages_figures_are_the_models():
    """docs/real-robot.md: where a side sensor stops detecting for a few gains, and how
    fast the table's response falls per millimetre."""
    from pathlib import Path

    from puckboard.ir_response import CALIBRATED, TABLE

    text = " ".join(
        (Path(__file__).resolve().parents[2] / "docs" / "real-robot.md")
        .read_text(encoding="utf-8")
        .split()
    )

    def end_mm(gain: float) -> str:
        end = MODEL.detection_end("right", gain, 0.0)
        assert end is not None
        return f"{end * 1000:.1f}"

    assert (
        f"a side sensor of gain 0.8 stops detecting a white wall straight ahead at "
        f"{end_mm(0.8)} mm instead of {end_mm(1.0)} mm" in text
    )
    assert f"0.7 to 1.3, moves that from {end_mm(0.7)} to {end_mm(1.3)} mm" in text
    # between the table's points from 5 mm to 5 cm, the fall per mm of C(d) = T(d) - T(inf)
    d, c = TABLE[1:8, 0] * 1000, CALIBRATED[1:8]
    per_mm = 100 * np.log(c[:-1] / c[1:]) / np.diff(d)
    assert f"falls by {per_mm.min():.0f} to {per_mm.max():.0f} % for each millimetre" in text
