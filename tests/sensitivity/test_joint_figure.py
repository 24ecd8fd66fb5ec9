"""The joint figure says what the text says: each profile's shipped value, titles that
do not run together, and no ranked chart where nothing is ranked."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from puckboard.profile import get_profile, profile_values
from puckboard.sensitivity.joint import JointResult, analyse_rows
from puckboard.sensitivity.joint.report import format_analysis

pytest.importorskip("matplotlib")


def _rows(profile: str, n: int, driven: bool, seed: int = 1) -> list[dict]:
    """Plausible robots of ``profile``: success set by the left body_radius (or by nothing)."""
    rng = np.random.default_rng(seed)
    shipped = profile_values(get_profile(profile))["body_radius"]
    rows = []
    for s in range(n):
        radius = shipped * rng.uniform(0.95, 1.05)
        rate = 0.9 - 0.8 * (radius / shipped - 0.95) / 0.1 if driven else 0.5
        success = bool(rng.uniform() < rate)
        rows.append({
            "key": f"{profile}{s}", "scenario": "two-robot-pass", "controller": "improved",
            "seed": s, "params": json.dumps({"robot.profile": profile, "variation": "plausible"}),
            "success": success, "failure": "" if success else "collision",
            "progress_laps": (0.7 if success else 0.3) + rng.normal(0, 0.05),
            "robot.left.profile_values": json.dumps(
                {"body_radius": radius, "ir_gain": rng.uniform(0.7, 1.3)}),
        })  # fmt: skip
    return rows


@pytest.fixture(scope="module")
def two_profiles():
    """One analysis per profile, the first number clear in both (analysed once: the
    regressions are the slow part)."""
    return analyse_rows([*_rows("epuck", 150, True), *_rows("epuck-vrep", 150, True, 2)])


def _result(analyses) -> JointResult:
    return JointResult("two-robot-pass", ("improved",), tuple(a.profile for a in analyses),
                       "0:300", 4, analyses)  # fmt: skip


def _figure(analyses):
    from puckboard.sensitivity.joint.plot import joint_figure

    return joint_figure(_result(analyses))


def test_two_profiles_each_draw_their_own_shipped_value(two_profiles):
    analyses = two_profiles
    assert [a.profile for a in analyses] == ["epuck", "epuck-vrep"]
    fig = _figure(analyses)
    panel = next(ax for ax in fig.axes if "body_radius" in ax.get_title())
    dashed = sorted(
        round(line.get_xdata()[0], 2) for line in panel.get_lines() if line.get_linestyle() == "--"
    )
    wanted = sorted(round(1000 * profile_values(get_profile(p))["body_radius"], 2)
                    for p in ("epuck", "epuck-vrep"))  # fmt: skip
    assert dashed == wanted and dashed[0] != dashed[1]


def test_panel_titles_put_robot_and_number_on_lines_of_their_own(two_profiles):
    titles = [ax.get_title() for ax in _figure(two_profiles[:1]).axes[1:]]
    assert "left:\nbody_radius (mm)" in titles


def test_nothing_ranked_draws_no_chart_and_says_what_the_text_says():
    (a,) = analyse_rows(_rows("epuck", 150, False))
    assert a.clear == []
    assert "the numbers are not ranked" in format_analysis(a, "improved")
    fig = _figure([a])
    assert fig.axes == []  # no chart, no panels
    text = "\n".join(t.get_text() for t in fig.texts)  # the heading among them
    assert "nothing is clear at N = 150: the numbers are not ranked" in text


def test_one_pair_is_one_pair(two_profiles):
    a = two_profiles[0]
    assert a.interaction is not None and a.interaction.pairs_tested == 1
    text = format_analysis(a, "improved")
    assert "of 1 pair" in text and "of 1 pairs" not in text


def test_ranked_by_progress_the_panels_plot_progress(two_profiles):
    from puckboard.sensitivity.joint import PROGRESS

    a = dataclasses.replace(two_profiles[0], ranked_by=PROGRESS)
    fig = _figure([a])
    labels = {ax.get_ylabel() for ax in fig.axes[1:]} - {""}
    assert labels == {"progress (laps)"}
