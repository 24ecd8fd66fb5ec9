"""``puckboard emulate`` as a user runs it: a separate process, a client, a JSON verdict."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import time

import pytest

from puckboard.backends.epuck import open_wifi
from puckboard.cli import main as cli_main
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

    assert DEFAULT_WIFI_PORT == EMULATOR_WIFI_PORT
    with pytest.raises(ConnectionLostError, match=f"add --port {EMULATOR_WIFI_PORT}"):
        open_wifi("line-follow", host="127.0.0.1", connect_timeout=2.0)
