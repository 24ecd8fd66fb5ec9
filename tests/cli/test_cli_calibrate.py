"""``puckboard calibrate ir`` on the command line: the plan, and bad input as one line.

Runs against a robot are in tests/backends/epuck/test_calibrate_emulated.py.
"""

from __future__ import annotations

import re
import socket
import textwrap
from pathlib import Path

import doc_pages
import pytest

from puckboard.cli import main
from puckboard.profile import EPUCK

ROOT = Path(__file__).resolve().parents[2]


def one_error_line(capsys: pytest.CaptureFixture[str]) -> str:
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith("puckboard calibrate: error: "), captured.err
    assert "Traceback" not in captured.err
    return lines[0]


def test_dry_run_prints_the_plan_and_connects_to_nothing(capsys):
    assert main(["calibrate", "ir", "--dry-run"]) == 0
    out = capsys.readouterr().out
    assert out.startswith(
        f"robot: epuck (body radius {EPUCK.body_radius * 1000:g} mm, wheels "
        f"{EPUCK.wheel_radius * 1000:g} mm, axle {EPUCK.axle_length * 1000:g} mm)\n"
    )
    assert "21 stops, 0 to 60 mm back from touching in 3 mm steps" in out
    assert re.search(r"expected duration: about \d+ min \d\d s", out)
    assert out.rstrip().endswith("(--dry-run: nothing was connected, nothing moved)")


def test_the_real_robot_page_shows_what_dry_run_prints(capsys):
    """docs/real-robot.md shows the plan of a dry run: that very output, every number."""
    page = (ROOT / "docs" / "real-robot.md").read_text(encoding="utf-8")
    # the block is a step of a numbered list, so it is indented
    fence = re.compile(r"^( *)```console\n(.*?)^\1```", re.MULTILINE | re.DOTALL)
    shown = [
        textwrap.dedent(m.group(2))
        for m in fence.finditer(page)
        if m.group(2).lstrip().startswith("$ puckboard calibrate ir --dry-run")
    ]
    assert len(shown) == 1
    command, _, output = shown[0].partition("\n")
    argv = command.removeprefix("$ puckboard ").split()
    assert main(argv) == 0
    doc_pages.assert_shown(output, capsys.readouterr().out, "docs/real-robot.md, the dry run")


def test_dry_run_follows_the_options_and_the_profile(tmp_path, capsys):
    mine = tmp_path / "mine.toml"
    mine.write_text('base = "epuck"\n[set]\nbody_radius = "35mm"\n', encoding="utf-8")
    argv = ["calibrate", "ir", "--dry-run", "--profile", str(mine), "--distance", "3cm"]
    assert main([*argv, "--step", "5mm", "--samples", "4", "--sample-period", "0.1"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("robot: mine (body radius 35 mm,")
    assert "7 stops, 0 to 30 mm back from touching in 5 mm steps (centre 35 to 65 mm" in out
    assert "4 readings per pose, 0.1 s apart, after 0.2 s to settle" in out


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        ([], "--out FILE.toml is needed: the profile file to write (or --dry-run"),
        (["--out", "x.txt"], "--out 'x.txt': profile files are TOML and end in .toml"),
        (["--out", "x.toml"], "no --backend: calibrate ir drives a real e-puck"),
        (["--out", "x.toml", "--backend", "embedded"], "--backend embedded: calibrate ir drives"),
        (["--dry-run", "--step", "0"], "--step: step must be at least 0.5 mm"),
        (["--dry-run", "--samples", "1"], "--samples: samples must be at least 2"),
        (["--dry-run", "--distance", "1m"], "--distance: distance must be more than 0 and at"),
        (["--dry-run", "--sample-period", "0"], "--sample-period: sample period must be more"),
        (["--dry-run", "--distance", "far"], "expected a distance in metres or with a unit"),
        (["--dry-run", "--profile", "epuck-vrep"], "senses with exact cones (V-REP's model)"),
        (["--dry-run", "--profile", "epuk"], "unknown robot profile 'epuk'"),
        (["--out", "x.toml", "--backend", "sercom"], "the sercom backend needs the serial device"),
        (["--out", "x.toml", "--backend", "epuck2-wifi", "--port", "70000"], "--port must be"),
        (["--out", "epuck.toml"], "the profile's name 'epuck' is a shipped profile's; give"),
        (["--out", "x.toml", "--name", "e-puck1"], "the profile's name 'e-puck1' is a shipped"),
    ],
)
def test_bad_input_is_one_line_and_status_2(argv, expected, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["calibrate", "ir", *argv]) == 2
    assert expected in one_error_line(capsys)
    assert not (tmp_path / "x.toml").exists()


def test_a_broken_profile_file_is_one_line_and_status_2(tmp_path, capsys):
    broken = tmp_path / "broken.toml"
    broken.write_text('base = "epuck"\n[set\n', encoding="utf-8")
    assert main(["calibrate", "ir", "--dry-run", "--profile", str(broken)]) == 2
    line = one_error_line(capsys)
    assert line.endswith("broken.toml:2:5: Expected ']' at the end of a table declaration")
    unknown = tmp_path / "unknown.toml"
    unknown.write_text('base = "epuck"\n[set]\n"ir_gain.rihgt" = 0.8\n', encoding="utf-8")
    assert main(["calibrate", "ir", "--dry-run", "--profile", str(unknown)]) == 2
    assert "ir_gain.rihgt" in one_error_line(capsys)


def test_no_robot_at_the_address_is_one_line(tmp_path, capsys):
    with socket.socket() as s:  # a port nobody listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    out = tmp_path / "x.toml"
    argv = ["calibrate", "ir", "--backend", "epuck2-wifi", "--host", "127.0.0.1"]
    assert main([*argv, "--port", str(port), "--out", str(out)]) == 2
    assert f"127.0.0.1:{port}" in one_error_line(capsys)
    assert not out.exists()


def test_the_time_left_follows_the_plan_not_the_pace_of_the_first_poses(monkeypatch, capsys):
    """Later stops drive further: told from the seconds per pose so far, the time left
    stayed "about 1 min" from stop 2 to the last. At the plan's own pace it is what the
    plan has left (issue 30, round 4, item 15)."""
    from puckboard.calibration.plan import make_plan
    from puckboard.calibration.readings import Progress
    from puckboard.cli import calibrate

    plan = make_plan(EPUCK)
    display = calibrate._Display(enabled=True, plan=plan)
    display.tty = False
    shown = []
    per_stop = 1 + len(plan.presentations)
    for stop in range(plan.stops):
        now = display.t0 + plan.duration(stop)  # exactly at the plan's pace
        monkeypatch.setattr(calibrate.time, "monotonic", lambda now=now: now)
        display.update(Progress(stop, plan.stops, 0.0, "front", ("front",), stop * per_stop, 99))
        left = re.search(r"about (\d+) min left", capsys.readouterr().err)
        assert left is not None
        shown.append(int(left.group(1)))
        assert display.seconds_left(stop, plan.duration(stop)) == pytest.approx(
            plan.duration() - plan.duration(stop)
        )
    assert shown == sorted(shown, reverse=True) and shown[0] > shown[-2] > 0


@pytest.mark.parametrize(("stops", "written"), [(1, False), (6, True)])
def test_ctrl_c_keeps_the_stops_measured(tmp_path, monkeypatch, capsys, stops, written):
    """Ctrl-C fits the poses measured so far and writes the profile when they suffice,
    and says why not otherwise; either way it exits 130 (issue 30, round 4, item 15)."""
    from calibration_helpers import known_profile, wall_robot

    import puckboard.calibration as calibration
    from puckboard.cli import calibrate

    monkeypatch.setattr(calibrate, "_open", lambda backend, options: wall_robot(known_profile()))
    real = calibration.run_calibration

    def interrupted(adapter, plan, model, progress=None):
        def ctrl_c_at_the_stop(p):
            if p.stop == stops:
                raise KeyboardInterrupt

        return real(adapter, plan, model, progress=ctrl_c_at_the_stop)

    monkeypatch.setattr(calibration, "run_calibration", interrupted)
    out = tmp_path / "mine.toml"
    argv = ["calibrate", "ir", "--backend", "epuck2-wifi", "--host", "10.0.0.9", "--out", str(out)]
    assert main([*argv, "-q", "--step", "6mm"]) == 130
    err = capsys.readouterr().err
    assert "interrupted; the wheels were stopped" in err
    assert out.exists() == written
    if written:
        assert f"fitting the {1 + stops * 8} of" in err
    else:
        assert "too few to fit" in err and "nothing was written" in err
