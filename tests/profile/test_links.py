"""The links' control timing: ranges with sources, draws quantised to the physics step,
``puckboard profiles show links`` and the table docs/profiles.md holds."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from puckboard.cli import main
from puckboard.cli.link_table import link_table_markdown
from puckboard.errors import ProfileError, SceneError
from puckboard.profile.links import LINKS, LinkTiming, draw_timing, get_link
from puckboard.scenario import load_scene
from puckboard.scenario.overrides import apply_scene_overrides
from puckboard.scenario.scene import Control, whole_steps
from puckboard.scenario.settings import link_settings

ROOT = Path(__file__).resolve().parents[2]


def test_the_links_the_issue_names_are_there_each_with_sources():
    for name in ("coppeliasim-sync", "epuck2-wifi", "bluetooth-sercom", "usb-sercom"):
        link = LINKS[name]
        assert link.sources and all(s.strip() for s in link.sources)
        assert 0 < link.period[0] <= link.period[1]
        assert 0 <= link.latency[0] <= link.latency[1]


def test_the_thesis_loop_is_the_default_loop():
    link = LINKS["coppeliasim-sync"]
    assert link.period == (0.05, 0.05) and link.latency == (0.0, 0.0) and not link.assumed
    assert load_scene("two-robot-pass").dt == link.period[0]


def test_the_bluetooth_lower_bound_is_the_bytes_at_115200_baud():
    # 59 bytes of one e-puck1 cycle, 10 bits each (8N1), at 115,200 bit/s
    assert LINKS["bluetooth-sercom"].latency[0] == pytest.approx(59 * 10 / 115_200, abs=1e-4)


def test_a_range_upside_down_is_refused():
    with pytest.raises(ValueError, match="latency must be 0 <= low <= high"):
        LinkTiming("x", "", (0.05, 0.05), (0.02, 0.01), ("s",), False)
    with pytest.raises(ValueError, match="period must be positive"):
        LinkTiming("x", "", (0.0, 0.05), (0.0, 0.0), ("s",), False)


@pytest.mark.parametrize("dt", [0.05, 0.01])
def test_draws_lie_in_the_range_and_run_rounded_to_whole_steps(dt):
    rng = np.random.default_rng(7)
    for name, link in LINKS.items():
        for _ in range(20):
            drawn = draw_timing(name, rng)
            for value, (low, high) in zip(drawn, (link.period, link.latency)):
                assert low <= value <= high
            control = Control.rounded(*drawn, dt)
            period, latency = control.period_for(dt), control.latency
            assert period >= dt
            for value, (low, high) in ((period, link.period), (latency, link.latency)):
                assert abs(value / dt - round(value / dt)) < 1e-9
                assert low - dt / 2 - 1e-12 <= value <= high + dt / 2 + 1e-12
            scene = apply_scene_overrides(
                load_scene("line-follow"), {"dt": dt, **link_settings(period, latency)}
            )
            assert scene.control.steps(dt)[0] >= 1


def test_a_time_rounds_to_the_nearest_whole_step_one_way():
    assert whole_steps(0.096, 0.05) == 0.1
    assert whole_steps(0.034, 0.05) == 0.05
    assert whole_steps(0.02, 0.05) == 0.0
    assert whole_steps(0.02, 0.05, minimum=1) == 0.05
    assert Control.rounded(0.096, 0.034, 0.05) == Control(period=0.1, latency=0.05)


def test_draws_are_seeded_and_take_two_numbers_whatever_the_link():
    a = np.random.default_rng(3)
    b = np.random.default_rng(3)
    assert draw_timing("epuck2-wifi", a) == draw_timing("epuck2-wifi", b)
    draw_timing("coppeliasim-sync", a)
    draw_timing("bluetooth-sercom", b)
    assert a.random() == b.random()


def test_an_unknown_link_names_the_known_ones():
    with pytest.raises(
        ProfileError, match="unknown link 'carrier-pigeon'; links: coppeliasim-sync"
    ):
        get_link("carrier-pigeon")


def test_profiles_show_lists_the_links_and_one_with_its_sources(capsys):
    assert main(["profiles", "show", "links"]) == 0
    out = capsys.readouterr().out
    assert all(name in out for name in LINKS)
    assert main(["profiles", "show", "epuck2-wifi"]) == 0
    out = capsys.readouterr().out
    assert "results_go_on_wifi_no_image.json" in out and "bluetooth" not in out
    assert main(["profiles", "show", "links", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert [r["name"] for r in rows] == list(LINKS)


def test_the_docs_hold_the_links_table_of_the_code():
    doc = (ROOT / "docs" / "profiles.md").read_text(encoding="utf-8")
    assert link_table_markdown() in doc


def link_file(tmp_path, table: str, name: str = "mine") -> Path:
    path = tmp_path / f"{name}.toml"
    path.write_text(f'base = "epuck"\n\n[link]\n{table}\n', encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("table", "words"),
    [
        ("period = 0\nlatency = 0.01", "[link] period: expected seconds > 0"),
        ("period = 0.05\nlatency = -1", "[link] latency: expected seconds >= 0"),
        ("period = 50\nlatency = 0.01", "[link] period: expected seconds > 0 and <= 1"),
        ("period = 0.05", "[link] latency: expected seconds"),
        ("period = 0.05\nlatency = 0.01\nlatncy = 2", "[link] unknown key 'latncy'"),
        ("period = 0.05\nlatency = 0.01\ncycle = 3", "[link] cycle: expected a table of numbers"),
    ],
)
def test_a_bad_link_table_is_one_line_naming_the_file(tmp_path, table, words):
    from puckboard.profile import load_profile_file

    with pytest.raises(ProfileError, match=r"mine\.toml") as info:
        load_profile_file(link_file(tmp_path, table))
    assert words in str(info.value) and "\n" not in str(info.value)


def test_a_profiles_link_is_stored_with_it_and_read_back(tmp_path):
    from puckboard.profile import load_profile_file, profile_from_data, profile_to_data

    profile = load_profile_file(link_file(tmp_path, 'period = 0.08\nlatency = 0.02\nsource = "m"'))
    assert profile.link == (0.08, 0.02) and profile.sources["link"] == "m"
    again = profile_from_data(profile_to_data(profile))
    assert again == profile and again.sources["link"] == "m"


def test_robots_with_different_links_cannot_share_one_loop(tmp_path):
    import dataclasses

    from puckboard.profile import load_profile_file
    from puckboard.scenario.robot_profiles import link_control

    a = load_profile_file(link_file(tmp_path, "period = 0.1\nlatency = 0.0", "a"))
    b = load_profile_file(link_file(tmp_path, "period = 0.2\nlatency = 0.0", "b"))
    scene = load_scene("two-robot-pass")
    left, right = scene.robots
    mixed = dataclasses.replace(
        scene, robots=(dataclasses.replace(left, profile=a), dataclasses.replace(right, profile=b))
    )
    with pytest.raises(SceneError, match="measured different links"):
        link_control(mixed)
    same = scene.with_profile(a)
    assert link_control(same).control.steps(scene.dt) == (2, 0)
    assert link_control(scene) is scene  # no link measured: the loop as it was
