"""Measuring a link: the adapters time their own round trips, the emulator can hold its
replies back by a link's latency, ``calibrate link`` writes the ``[link]`` table, and a
profile with one runs the simulator at that timing.

The emulator's delays and the measurement share one fake clock that only the delays move,
so what is measured is exactly what was injected, however busy the machine.
"""

from __future__ import annotations

import json
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

from puckboard.backends.epuck import open_sercom, open_wifi
from puckboard.calibration.link import LinkMeasurement, Spread, measure_link, write_link_table
from puckboard.cli import main
from puckboard.control.emulation import Emulation
from puckboard.profile import load_profile_file
from puckboard.profile.links import LinkTiming

pytestmark = pytest.mark.network

ROOT = Path(__file__).resolve().parents[3]


class FakeClock:
    """Time that passes only when the emulator waits out a reply's delay."""

    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t

    def sleep(self, seconds: float) -> None:
        self.t += seconds


def fixed(latency: float) -> LinkTiming:
    return LinkTiming("test", "a fixed delay", (0.05, 0.05), (latency, latency), ("test",), True)


@contextmanager
def emulated(protocol: str, link: LinkTiming, clock: FakeClock | None) -> Iterator[Emulation]:
    serial = "tcp" if protocol == "sercom" else None
    em = Emulation(
        "line-follow", protocol=protocol, serial=serial, until_client_leaves=False,
        idle_timeout=None, link=link,
    )  # fmt: skip
    if clock is not None:
        em.server.sleep = clock.sleep
    thread = threading.Thread(target=em.run, args=(60.0,), daemon=True)
    thread.start()
    try:
        yield em
    finally:
        em.stop()
        thread.join(5)


@pytest.mark.parametrize(("protocol", "cycle"), [("wifi", 0.06), ("sercom", 0.03)])
def test_the_adapter_times_its_round_trips_and_the_cycle_adds_the_command(protocol, cycle):
    clock = FakeClock()
    with emulated(protocol, fixed(0.03), clock) as em:
        opener = open_wifi if protocol == "wifi" else open_sercom
        connection = opener("line-follow", **em.info.options)
        adapter = next(iter(connection.adapters.values()))
        adapter.link.clock = clock
        try:
            measured = measure_link(adapter, 6, clock=clock)
        finally:
            connection.close()
    assert measured.round_trip.n == 6
    assert measured.latency == pytest.approx(0.03)
    # Wi-Fi acknowledges a wheel command (one more delayed reply); sercom does not
    assert measured.period == pytest.approx(cycle)


def test_the_emulators_link_delays_lie_in_the_links_range():
    link = LinkTiming("x", "", (0.05, 0.05), (0.01, 0.02), ("t",), True)
    clock = FakeClock()
    with emulated("wifi", link, clock) as em:
        delays = [em.server.reply_delay() for _ in range(50)] if em.server.reply_delay else []
    assert len(delays) == 50 and all(0.01 <= d <= 0.02 for d in delays)
    assert len(set(delays)) > 1  # drawn, not fixed


def measurement(period: float, latency: float) -> LinkMeasurement:
    return LinkMeasurement(
        round_trip=Spread(10, latency, latency / 2, latency * 2, latency * 3),
        cycle=Spread(10, period / 2, period / 3, period, period * 2),
    )


def test_the_link_table_goes_into_an_existing_profile_file_once(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text((ROOT / "examples" / "my-epuck.toml").read_text(encoding="utf-8"))
    write_link_table(path, measurement(0.08, 0.03), "first", base="epuck", name="mine")
    write_link_table(path, measurement(0.12, 0.04), "second", base="epuck", name="mine")
    text = path.read_text(encoding="utf-8")
    assert text.count("[link]") == 1 and '"second"' in text
    profile = load_profile_file(path)
    assert profile.link == (0.12, 0.04)
    assert profile.sources["link"] == "second"
    assert dict(profile.overrides)["ir_gain.right"] == 0.83  # the rest of the file kept


def test_a_profiles_link_runs_the_simulator_at_that_timing(tmp_path, capsys):
    path = tmp_path / "slow.toml"
    write_link_table(path, measurement(0.11, 0.04), "measured", base="epuck", name="slow")
    assert main(["run", "line-follow", "--profile", str(path), "--duration", "2", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    # rounded to whole steps of 0.05 s: 0.11 -> 0.1, 0.04 -> 0.05
    assert d["control_period_s"] == pytest.approx(0.1)
    assert d["control_latency_s"] == pytest.approx(0.05)
    args = ["run", "line-follow", "--profile", str(path), "--duration", "2", "--json"]
    assert main([*args, "--set", "control.period=0.15"]) == 0  # the command line wins
    d = json.loads(capsys.readouterr().out)
    assert d["control_period_s"] == pytest.approx(0.15) and d["control_latency_s"] == 0.0


def test_on_the_robot_itself_a_profiles_link_is_the_link(tmp_path, capsys):
    """The one rule's third case: a robot's own link needs no simulating, so the run
    keeps the robot's pace (neither refused, as a simulator that cannot delay is, nor
    slowed to the file's period)."""
    path = tmp_path / "slow.toml"
    write_link_table(path, measurement(0.11, 0.04), "measured", base="epuck", name="slow")
    with emulated("wifi", fixed(0.0), None) as em:
        code = main([
            "run", "line-follow", "--backend", "epuck2-wifi", "--host", em.info.options["host"],
            "--port", str(em.info.options["port"]), "--profile", str(path), "--duration",
            "0.2", "--json",
        ])  # fmt: skip
    assert code == 0
    assert "control_period_s" not in json.loads(capsys.readouterr().out)


def test_calibrate_link_against_the_emulator_writes_a_loadable_profile(tmp_path, capsys):
    out = tmp_path / "bt.toml"
    with emulated("wifi", fixed(0.0), None) as em:
        code = main([
            "calibrate", "link", "--backend", "epuck2-wifi", "--host", em.info.options["host"],
            "--port", str(em.info.options["port"]), "--out", str(out), "--rounds", "4", "--json",
        ])  # fmt: skip
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    assert data["round_trip_s"]["n"] == 4 and data["cycle_s"]["n"] == 4
    profile = load_profile_file(out)
    assert profile.name == "bt" and profile.base == "epuck"
    assert profile.link == (pytest.approx(data["period_s"]), pytest.approx(data["latency_s"]))
    assert "calibrate link: 4 cycles over epuck2-wifi" in profile.sources["link"]


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--backend", "sercom", "--rounds", "1"], "--rounds must be at least 2"),
        (["--backend", "embedded"], "calibrate link drives a real e-puck"),
    ],
)
def test_bad_calibrate_link_input_is_one_line(tmp_path, capsys, args, words):
    base = ["calibrate", "link", "--out", str(tmp_path / "x.toml")]
    assert main([*base, "--device", "/dev/null-none", *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0], err


def test_emulate_refuses_an_unknown_link(capsys):
    assert main(["emulate", "line-follow", "--link", "carrier-pigeon"]) == 2
    err = capsys.readouterr().err.strip()
    assert "--link 'carrier-pigeon': unknown link; links: coppeliasim-sync" in err


def calibrate_on(em: Emulation, out: Path, *more: str) -> int:
    return main([
        "calibrate", "link", "--backend", "epuck2-wifi", "--host", em.info.options["host"],
        "--port", str(em.info.options["port"]), "--out", str(out), *more,
    ])  # fmt: skip


def test_ctrl_c_keeps_the_cycles_timed_and_writes_them(tmp_path, capsys, monkeypatch):
    """As calibrate ir fits the stops it measured: 3 of 100000 cycles are written."""
    from puckboard.sweep.progress import PlainProgress

    advance = PlainProgress.advance

    def ctrl_c_at_the_third(self, n):
        advance(self, n)
        if self.done == 3:
            raise KeyboardInterrupt

    monkeypatch.setattr(PlainProgress, "advance", ctrl_c_at_the_third)
    out = tmp_path / "slow.toml"
    with emulated("wifi", fixed(0.0), None) as em:
        assert calibrate_on(em, out, "--rounds", "100000") == 130
    captured = capsys.readouterr()
    assert "interrupted; keeping the 3 of 100000 cycles timed before Ctrl-C" in captured.err
    assert "round trip (sense): median" in captured.out and "wrote [link]" in captured.out
    assert "3 cycles over epuck2-wifi" in load_profile_file(out).sources["link"]


def test_progress_is_shown_on_a_log_too(tmp_path, capsys):
    with emulated("wifi", fixed(0.0), None) as em:
        assert calibrate_on(em, tmp_path / "a.toml", "--rounds", "4") == 0
    assert "calibrate link: 4/4 cycles (100 %)" in capsys.readouterr().err


def test_a_write_that_fails_loses_no_measurement(tmp_path, capsys, monkeypatch):
    from puckboard.calibration import link
    from puckboard.errors import ProfileError

    def refuse(path, *args, **kwargs):
        raise ProfileError("the disk is full")

    monkeypatch.setattr(link, "write_link_table", refuse)
    out = tmp_path / "a.toml"
    with emulated("wifi", fixed(0.0), None) as em:
        assert calibrate_on(em, out, "--rounds", "4") == 1
    captured = capsys.readouterr()
    assert "round trip (sense): median" in captured.out and "whole cycle" in captured.out
    assert captured.err.strip().splitlines()[-1] == (
        f"puckboard calibrate: error: {out}: not updated (the disk is full); the measurement "
        "is printed above"
    )


@pytest.mark.parametrize(
    ("text", "said"),
    [
        ("[[broken", "not a TOML file (Expected ']]'"),
        ("hello = 3\n", "unknown key 'hello'"),
    ],
)
def test_an_out_file_that_is_no_profile_is_refused_before_measuring(tmp_path, capsys, text, said):
    out = tmp_path / "x.toml"
    out.write_text(text, encoding="utf-8")
    args = ["calibrate", "link", "--backend", "sercom", "--device", "/dev/null-none"]
    assert main([*args, "--out", str(out)]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith(f"puckboard calibrate: error: {out}: {said}")
    assert line.endswith("; nothing was measured")
    assert out.read_text(encoding="utf-8") == text


def test_dry_run_says_what_link_would_do_and_a_port_in_the_host_points_to_port(capsys):
    assert main(["calibrate", "link", "--dry-run", "--rounds", "50"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("calibrate link: time 50 control cycles over the robot's link")
    assert "nothing was connected, nothing moved" in out
    args = ["calibrate", "link", "--backend", "epuck2-wifi", "--host", "127.0.0.1:38000"]
    assert main([*args, "--out", "x.toml"]) == 2
    assert capsys.readouterr().err.strip() == (
        "puckboard calibrate: error: --host '127.0.0.1:38000' holds a port; give it with "
        "--port: --host 127.0.0.1 --port 38000"
    )
