"""``puckboard replay``: the one-file player, the served one, and one line for bad input."""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import urllib.request

import numpy as np
import pytest

from puckboard.cli import COMMANDS, main

WALL_CLOCK = ("wall_s", "realtime_factor")


def one_error_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("puckboard replay: error: "), err
    return lines[0]


@pytest.fixture(scope="module")
def run_npz(tmp_path_factory):
    path = tmp_path_factory.mktemp("cli-replay") / "r.npz"
    assert main(["run", "two-robot-pass", "--record", str(path), "--json"]) == 0
    return path


def test_recording_the_tree_changes_no_result(tmp_path, capsys):
    assert main(["run", "two-robot-pass", "--seed", "2", "--json"]) == 0
    plain = json.loads(capsys.readouterr().out)
    record = str(tmp_path / "r.npz")
    assert main(["run", "two-robot-pass", "--seed", "2", "--json", "--record", record]) == 0
    recorded = json.loads(capsys.readouterr().out)
    for d in (plain, recorded):
        for key in WALL_CLOCK:
            d.pop(key)
    assert recorded == plain
    with np.load(record) as data:
        assert "tree" in data.files  # the tree was recorded


def test_replay_is_a_listed_command(capsys):
    assert "replay" in COMMANDS
    with pytest.raises(SystemExit):
        main(["--help"])
    assert re.search(r"^\s+replay\s+replay a recorded run", capsys.readouterr().out, re.M)


def test_the_html_player_is_written_in_one_file(run_npz, tmp_path, capsys):
    out = tmp_path / "course" / "r.html"
    assert main(["replay", str(run_npz), "--html", str(out)]) == 0
    line = capsys.readouterr().out.strip()
    assert line.startswith(f"wrote {out} (") and "MB" in line
    text = out.read_text(encoding="utf-8")
    assert '<script id="replay-data" type="application/json">' in text
    assert 'id="slider"' in text and "startReplay" in text


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ([], "say how to replay it: --web .* or --html FILE"),
        (["--html", "r.txt"], "--html 'r.txt': the player is written as a .html file"),
        (["--web", "--web-port", "70000"], "--web-port must be 0..65535, got 70000"),
    ],
)
def test_bad_options_are_one_line(run_npz, capsys, args, message):
    assert main(["replay", str(run_npz), *args]) == 2
    assert re.search(message, one_error_line(capsys))


def newer(path, tmp_path):
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files if k != "meta"}
        meta = json.loads(str(data["meta"]))
    meta["version"] = 99
    out = tmp_path / "newer.npz"
    np.savez(out, meta=np.array(json.dumps(meta)), **arrays)
    return out


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda run, tmp: tmp / "missing.npz", "no recording at"),
        (lambda run, tmp: (tmp / "x.npz").write_bytes(b"hello") and tmp / "x.npz",
         "is not a puckboard recording"),
        (lambda run, tmp: (tmp / "cut.npz").write_bytes(run.read_bytes()[: run.stat().st_size // 2])
         and tmp / "cut.npz", "is not a puckboard recording"),
        (newer, "uses recording format 99; this puckboard reads up to 3: upgrade puckboard"),
    ],
    ids=["missing", "not-a-recording", "truncated", "newer-format"],
)  # fmt: skip
def test_bad_recordings_are_one_line_and_write_nothing(run_npz, tmp_path, capsys, make, message):
    path = make(run_npz, tmp_path)
    out = tmp_path / "r.html"
    assert main(["replay", str(path), "--html", str(out)]) == 2
    assert message in one_error_line(capsys)
    assert not out.exists()


@pytest.mark.skipif(sys.platform == "win32", reason="Ctrl-C as a signal")
def test_the_served_player_answers_until_ctrl_c(run_npz):
    pytest.importorskip("aiohttp")
    proc = subprocess.Popen(
        [sys.executable, "-m", "puckboard", "replay", str(run_npz), "--web", "--web-port", "0"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )  # fmt: skip
    try:
        assert proc.stderr is not None
        line = proc.stderr.readline()
        url = re.search(r"replay: (http://\S+)", line).group(1)
        with urllib.request.urlopen(url + "replay.json", timeout=10) as response:
            data = json.loads(response.read())
        assert [r["name"] for r in data["robots"]] == ["left", "right"]
        proc.send_signal(signal.SIGINT)
        assert proc.wait(10) == 130  # Ctrl-C, as every command ends on it
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
