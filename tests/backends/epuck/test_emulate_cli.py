"""``puckboard emulate`` as a user runs it: a separate process, a client, a JSON verdict."""

from __future__ import annotations

import json
import re
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator

import pytest

from puckboard.backends.epuck import open_wifi
from puckboard.cli import main as cli_main
from puckboard.control.emulation import Emulation
from puckboard.errors import ConnectionLostError

pytestmark = pytest.mark.network

RUN_JSON_FIELDS = {
    "scenario", "controller", "seed", "dt_s", "steps", "sim_time_s", "wall_s",
    "realtime_factor", "success", "failure", "failures", "robots", "events",
}  # fmt: skip


def test_emulate_serves_wifi_and_prints_the_verdict_as_json() -> None:
    proc = subprocess.Popen(
        [sys.executable, "-m", "puckboard", "emulate", "line-follow", "--protocol", "wifi",
         "--port", "0", "--duration", "1", "--json"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert proc.stderr is not None
        banner = proc.stderr.readline()
        match = re.search(r"at 127\.0\.0\.1:(\d+)", banner)
        assert match, banner
        conn = open_wifi("line-follow", host="127.0.0.1", port=int(match.group(1)), timeout=0.5)
        robot = conn.adapters["epuck"]

        def drive_until_lost() -> None:
            deadline = time.monotonic() + 10
            while time.monotonic() < deadline:
                robot.sense_all()
                robot.set_wheel_speeds(2.0, 2.0)
                time.sleep(0.02)

        with pytest.raises(ConnectionLostError):  # the emulator ends after 1 s of robot time
            drive_until_lost()
        conn.close()
        out, err = proc.communicate(timeout=10)
    finally:
        proc.kill()
    assert proc.returncode == 0, err
    verdict = json.loads(out)
    assert set(verdict) == RUN_JSON_FIELDS
    assert verdict["scenario"] == "line-follow"
    assert verdict["steps"] == 20  # 1 s at dt = 0.05 s, counted from the first command
    assert verdict["robots"][0]["distance_m"] > 0.005  # it drove


def test_emulate_explains_missing_pty(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    import puckboard.backends.epuck.emulator

    monkeypatch.setattr(puckboard.backends.epuck.emulator, "pty_available", lambda: False)
    assert cli_main(["emulate", "--protocol", "sercom"]) == 2
    err = capsys.readouterr().err
    assert "socket://" in err and "--protocol wifi" in err


def test_emulate_rejects_bad_duration(capsys: pytest.CaptureFixture[str]) -> None:
    assert cli_main(["emulate", "--duration", "-1"]) == 2
    assert "--duration" in capsys.readouterr().err


def test_connecting_to_this_machine_on_the_robot_port_suggests_the_emulator_port() -> None:
    """The emulator cannot bind the robot's port 1000 without rights; a client that
    forgets --port is told which port the emulator uses."""
    from puckboard.backends.epuck.factories import EMULATOR_WIFI_PORT
    from puckboard.cli.emulate import DEFAULT_WIFI_PORT

    # two definitions (the command line's keeps --help from importing the backend): the
    # emulator must listen where the client's hint sends the user
    assert DEFAULT_WIFI_PORT == EMULATOR_WIFI_PORT
    with pytest.raises(ConnectionLostError, match=f"add --port {EMULATOR_WIFI_PORT}"):
        open_wifi("line-follow", host="127.0.0.1", connect_timeout=2.0)


@pytest.fixture
def emulator() -> Iterator[Emulation]:
    """``puckboard emulate`` in this process, on a free port, as a user starts it (it
    stands in for the physical robot: profile epuck)."""
    em = Emulation("line-follow", protocol="wifi", port=0, idle_timeout=None)
    thread = threading.Thread(target=em.run, args=(60.0,), daemon=True)
    thread.start()
    try:
        yield em
    finally:
        em.stop()
        thread.join(5)
        assert not thread.is_alive(), "the emulator did not stop"


def run_against(em: Emulation, *more: str) -> int:
    port = str(em.info.options["port"])
    return cli_main(
        ["run", "line-follow", "--backend", "epuck2-wifi", "--host", "127.0.0.1", "--port", port,
         *more]
    )  # fmt: skip


def test_run_against_the_emulator_reports_the_profile_of_the_robot_it_drove(
    emulator: Emulation, capsys: pytest.CaptureFixture[str]
) -> None:
    assert emulator.scene.robots[0].profile == "epuck"  # what the emulator serves
    assert run_against(emulator, "--duration", "0.5", "--json") == 0
    verdict = json.loads(capsys.readouterr().out)
    assert [r["profile"] for r in verdict["robots"]] == ["epuck"]  # not the scene's epuck-vrep


def test_an_emulator_that_goes_away_mid_run_ends_in_one_line(
    emulator: Emulation,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    caplog: pytest.LogCaptureFixture,
) -> None:
    from puckboard.control.loop import ControlLoop

    original = ControlLoop.cycle

    def cycle(loop: ControlLoop) -> None:
        if loop.cycles == 10:
            emulator.stop()  # the emulator ends, and closes its connection
        original(loop)

    monkeypatch.setattr(ControlLoop, "cycle", cycle)
    assert run_against(emulator, "--duration", "30", "--json") == 1  # --json: no progress line
    err = capsys.readouterr().err
    assert "Traceback" not in err and "Traceback" not in caplog.text
    assert len(err.strip().splitlines()) == 1, err
    line = err.strip()
    assert re.match(
        r"puckboard run: error: the epuck2-wifi connection was lost at t = \d+\.\d\d s of run "
        r"time and no stop command reached 'epuck': check that it is not still driving\. ",
        line,
    ), line
    assert "127.0.0.1" in line  # what was lost


@pytest.mark.skipif(sys.platform == "win32", reason="Ctrl-C is not a signal one can send there")
def test_ctrl_c_on_emulate_with_a_client_driving_says_it_was_interrupted() -> None:
    proc = subprocess.Popen(
        [sys.executable, "-m", "puckboard", "emulate", "line-follow", "--port", "0"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert proc.stdout is not None
        match = re.search(r"at 127\.0\.0\.1:(\d+)", proc.stdout.readline())
        assert match
        conn = open_wifi("line-follow", host="127.0.0.1", port=int(match.group(1)), timeout=0.5)
        robot = conn.adapters["epuck"]
        for _ in range(20):  # a client drives for a moment
            robot.sense_all()
            robot.set_wheel_speeds(2.0, 2.0)
            time.sleep(0.02)
        proc.send_signal(signal.SIGINT)  # Ctrl-C, with the client still connected
        out, err = proc.communicate(timeout=10)
        conn.close()
    finally:
        proc.kill()
    assert proc.returncode == 130, err
    verdict = [line for line in out.splitlines() if line.startswith("line-follow: ")]
    assert len(verdict) == 1, out
    assert "(ended: interrupted by Ctrl-C; a client was driving)" in verdict[0]
    assert "duration" not in verdict[0]


@pytest.mark.skipif(sys.platform == "win32", reason="Ctrl-C is not a signal one can send there")
def test_ctrl_c_on_emulate_before_any_client_gives_no_verdict() -> None:
    proc = subprocess.Popen(
        [sys.executable, "-m", "puckboard", "emulate", "line-follow", "--port", "0"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert proc.stdout is not None
        banner = [proc.stdout.readline() for _ in range(3)]  # the last is said as it waits
        assert "at 127.0.0.1:" in banner[0] and "Ctrl-C" in banner[2], banner
        proc.send_signal(signal.SIGINT)  # Ctrl-C with nobody connected
        out, err = proc.communicate(timeout=10)
    finally:
        proc.kill()
    assert proc.returncode == 130, err
    verdict = [line for line in out.splitlines() if line.startswith("line-follow: ")]
    assert verdict == [
        "line-follow: no run (interrupted by Ctrl-C before any client connected)"
    ], out
    assert "timeout" not in out and "failure" not in out
