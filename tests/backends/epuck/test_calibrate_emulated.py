"""``puckboard calibrate ir`` against ``puckboard emulate``: the promise end to end.

The emulated robot's sensors have known, different gains and offsets, given to
``emulate`` by a profile file, as a student would give a robot; the calibration talks to
it over the e-puck2 Wi-Fi protocol (or sercom) exactly as to a real robot, and must find
every gain within 5 % and every offset within 10 raw units. The emulator runs 20 times
faster than real time, so a calibration of 11 stops takes ten to twenty seconds.
"""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from calibration_helpers import KNOWN_GAINS, KNOWN_OFFSETS, known_profile, write_known_file

from puckboard.cli import main as cli_main
from puckboard.control.emulation import Emulation

pytestmark = pytest.mark.network

SPEED = 20.0
#: The test's plan: the default distance in 6 mm steps, 20 readings 2.5 ms of wall time
#: apart (0.05 s of the robot's time, one of its steps).
FAST = ["--step", "6mm", "--samples", "20", "--sample-period", "0.0025"]


def calibrate(port: int | str, out: Path, *extra: str, backend: str = "epuck2-wifi") -> list[str]:
    link = ["--host", "127.0.0.1", "--port", str(port)] if backend == "epuck2-wifi" else []
    return ["calibrate", "ir", "--backend", backend, *link, "--out", str(out), *FAST, *extra]


@pytest.mark.slow
def test_calibrate_finds_the_emulated_robots_known_gains_and_the_file_is_usable(tmp_path, capsys):
    known = write_known_file(tmp_path)
    emulator = subprocess.Popen(
        [sys.executable, "-m", "puckboard", "emulate", "calibration-wall", "--profile", str(known),
         "--port", "0", "--speed", str(SPEED), "--duration", "3600", "--json"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert emulator.stderr is not None
        banner = emulator.stderr.readline()
        port = re.search(r"at 127\.0\.0\.1:(\d+)", banner)
        assert port, banner
        out = tmp_path / "x.toml"
        assert cli_main(calibrate(port.group(1), out, "--json")) == 0
        verdict, _ = emulator.communicate(timeout=20)
    finally:
        emulator.kill()
    report = json.loads(capsys.readouterr().out)
    fitted = {s["sensor"]: s for s in report["sensors"]}
    for name, gain in KNOWN_GAINS.items():
        assert fitted[name]["gain"] == pytest.approx(gain, rel=0.05), name
        assert fitted[name]["offset"] == pytest.approx(KNOWN_OFFSETS[name], abs=10.0), name
    assert report["ambient"]["changed"] == []  # the emulator's room light is steady
    assert json.loads(verdict)["scenario"] == "calibration-wall"  # it served the whole run

    # the file: base epuck, per-sensor gains and offsets with the fit as their source
    assert cli_main(["profiles", "show", str(out)]) == 0
    shown = capsys.readouterr().out
    assert shown.startswith("x (changes epuck)\n")
    for name in KNOWN_GAINS:
        row = next(line for line in shown.splitlines() if line.split()[:1] == [f"ir_gain.{name}"])
        assert float(row.split()[1]) == pytest.approx(fitted[name]["gain"], abs=1e-4)
    assert shown.count("set: puckboard calibrate ir, ") == 16  # 8 gains, 8 offsets

    # and a run with it simulates that robot
    assert cli_main(["run", "two-robot-pass", "--profile", str(out), "--json"]) == 0
    run = json.loads(capsys.readouterr().out)
    assert {r["profile"] for r in run["robots"]} == {"x"}
    values = run["robots"][0]["profile_values"]
    assert values["ir_gain.right"] == pytest.approx(fitted["right"]["gain"], abs=1e-4)


def serve(protocol: str, *, serial: str | None = None) -> tuple[Emulation, threading.Thread]:
    emulation = Emulation(
        "calibration-wall", protocol=protocol, serial=serial, profile=known_profile(),
        realtime=SPEED, idle_timeout=None, until_client_leaves=False,
    )  # fmt: skip
    thread = threading.Thread(target=emulation.run, args=(3600.0,), daemon=True)
    thread.start()
    return emulation, thread


def test_calibrate_over_sercom_writes_a_profile(tmp_path, capsys):
    pytest.importorskip("serial")
    from puckboard.backends.epuck.emulator import pty_available

    # a pseudo-terminal where there is one: over TCP, a wheel command with no reply and
    # the request after it wait for each other (Nagle's algorithm), 40 ms a move's poll
    emulation, thread = serve("sercom", serial="pty" if pty_available() else "tcp")
    try:
        out = tmp_path / "short.toml"
        # four stops: at the first, touching, a strong sensor reads close enough to full
        # scale that its noise may reach it, and the fit rightly leaves that pose out; the
        # other three are still enough (with three stops, one left out is a failed fit)
        argv = calibrate(0, out, "--distance", "18mm", backend="sercom")
        argv += ["--device", emulation.info.options["device"], "-q"]
        assert cli_main(argv) == 0
    finally:
        emulation.stop()
        thread.join(5)
    printed = capsys.readouterr().out
    assert "8 IR sensors fitted from 33 poses" in printed  # facing + 4 stops × 8
    assert f"wrote {out} (base epuck)" in printed
    assert emulation.robot.speeds == (0, 0)


def _calibrate_in_a_process(port: int, out: Path) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-m", "puckboard", *calibrate(port, out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip


def _wait_for_progress(proc: subprocess.Popen[str]) -> str:
    assert proc.stderr is not None
    seen = ""
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline:
        line = proc.stderr.readline()
        seen += line
        if line.startswith("stop 2/"):
            return seen
    raise AssertionError(f"no progress within 20 s: {seen}")


@pytest.mark.skipif(os.name != "posix", reason="SIGINT to a child process: POSIX")
def test_ctrl_c_stops_the_wheels_and_exits_130(tmp_path):
    emulation, thread = serve("wifi")
    try:
        out = tmp_path / "x.toml"
        proc = _calibrate_in_a_process(emulation.info.options["port"], out)
        try:
            seen = _wait_for_progress(proc)
            proc.send_signal(signal.SIGINT)
            _, err = proc.communicate(timeout=20)
        finally:
            proc.kill()
        time.sleep(0.2)
        assert emulation.robot.speeds == (0, 0)
    finally:
        emulation.stop()
        thread.join(5)
    assert proc.returncode == 130, seen + err
    lines = err.strip().splitlines()
    assert "puckboard calibrate: interrupted; the wheels were stopped" in lines
    # stopped at the first pose: what was measured is kept, but too little to fit
    assert "too few to fit" in lines[-1] and "nothing was written" in lines[-1]
    assert "Traceback" not in err
    assert not out.exists()


def test_a_lost_link_is_one_line_and_status_1(tmp_path):
    emulation, thread = serve("wifi")
    try:
        out = tmp_path / "x.toml"
        proc = _calibrate_in_a_process(emulation.info.options["port"], out)
        try:
            seen = _wait_for_progress(proc)
            emulation.server.drop_client()
            _, err = proc.communicate(timeout=30)
        finally:
            proc.kill()
    finally:
        emulation.stop()
        thread.join(5)
    assert proc.returncode == 1, seen + err
    last = err.strip().splitlines()[-1]
    assert last.startswith("puckboard calibrate: error: the connection to the robot was lost (")
    assert "Traceback" not in err
    assert not out.exists()
