"""Every output path and every port is checked by one shared check before any work:
a path through a regular file, a port out of range or in use is one line, exit 2, and
nothing ran (issue 30, round 4, item 8)."""

from __future__ import annotations

import socket
from pathlib import Path

import pytest

from puckboard.cli import main


@pytest.fixture
def blocker(tmp_path: Path) -> Path:
    """A regular file: no folder can be made under it, whoever runs the tests."""
    path = tmp_path / "blocker"
    path.write_text("a file, not a folder", encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def run_npz(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("outputs") / "r.npz"
    assert main(["run", "line-follow", "--duration", "0.5", "--record", str(path), "--json"]) == 0
    return path


def refused(capsys: pytest.CaptureFixture[str], command: str) -> str:
    """The one error line of a command refused before it did anything."""
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith(f"puckboard {command}: error: "), captured.err
    assert "wrote" not in captured.out and "episodes" not in captured.out, captured.out
    return lines[0]


@pytest.mark.parametrize(
    ("argv", "flag"),
    [
        (
            ["sweep", "--seeds", "0:1", "--duration", "0.2", "--workers", "1", "-q", "--out"],
            "--out",
        ),
        (
            ["sweep", "--seeds", "0:1", "--duration", "0.2", "--workers", "1", "-q",
             "--set", "noise.proximity=0,0.1", "--plot"],
            "--plot",
        ),
        (["sensitivity", "--seeds", "0:1", "--duration", "0.2", "--workers", "1", "-q",
          "--plot"], "--plot"),
        (["bench", "--suite", "core", "--steps", "1", "--out"], "--out"),
    ],
)  # fmt: skip
def test_outputs_through_a_file_are_refused_before_the_work(blocker, capsys, argv, flag):
    name = "x.png" if flag == "--plot" else "r.csv" if argv[0] == "sweep" else "b.json"
    assert main([*argv, str(blocker / name)]) == 2
    line = refused(capsys, argv[0])
    assert flag in line and "'" + str(blocker) + "' is a file, not a folder" in line


def test_plot_refuses_an_out_folder_that_is_a_file(run_npz, blocker, capsys):
    assert main(["plot", str(run_npz), "--out", str(blocker)]) == 2
    assert "is a file, not a folder" in refused(capsys, "plot")


def test_plot_refuses_an_animation_it_could_not_write_before_any_plot(
    run_npz, blocker, tmp_path, capsys
):
    out = tmp_path / "plots"
    assert main(["plot", str(run_npz), "--out", str(out), "--animate", str(blocker / "a.gif")]) == 2
    assert "--animate" in refused(capsys, "plot")
    assert not any(out.iterdir())  # not one plot written before the refusal


def test_replay_names_the_file_in_the_way_not_file_exists(run_npz, blocker, capsys):
    assert main(["replay", str(run_npz), "--html", str(blocker / "x.html")]) == 2
    line = refused(capsys, "replay")
    assert "is a file, not a folder" in line and "File exists" not in line


def test_docs_serve_refuses_a_port_out_of_range(capsys):
    assert main(["docs", "--serve", "--port", "99999"]) == 2
    assert "--port must be 0..65535, got 99999" in refused(capsys, "docs")


def test_docs_serve_refuses_a_port_in_use(capsys):
    with socket.create_server(("127.0.0.1", 0)) as taken:
        port = taken.getsockname()[1]
        assert main(["docs", "--serve", "--port", str(port)]) == 2
    assert "the port is in use" in refused(capsys, "docs")


def test_run_refuses_a_coppeliasim_port_out_of_range_at_once(capsys):
    assert main(["run", "--backend", "coppeliasim", "--port", "70000"]) == 2
    assert "--port must be 0..65535, got 70000" in refused(capsys, "run")


def test_serve_refuses_a_port_in_use_before_the_server_starts(capsys):
    with socket.create_server(("127.0.0.1", 0)) as taken:
        port = taken.getsockname()[1]
        assert main(["serve", "--port", str(port)]) == 2
    assert "the port is in use" in refused(capsys, "serve")
