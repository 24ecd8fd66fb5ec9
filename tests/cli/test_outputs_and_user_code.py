"""Outputs that cannot be written are refused before the run, and a student's broken
controller or example is shown as Python shows it, without puckboard's frames."""

from __future__ import annotations

import logging
import os
import sys
from pathlib import Path

import puckboard.examples
import pytest

import puckboard
from puckboard.cli import examples as examples_cli
from puckboard.cli import main

PACKAGE = Path(puckboard.__file__).parent


def error_lines(capsys: pytest.CaptureFixture[str], command: str) -> list[str]:
    """stderr's lines, checking that nothing ran (no stdout), that the last line is the
    command's one error line and that no frame of puckboard's own files is shown."""
    captured = capsys.readouterr()
    lines = captured.err.rstrip("\n").splitlines()
    assert captured.out == "", captured.out
    assert lines and lines[-1].startswith(f"puckboard {command}: error: "), captured.err
    assert str(PACKAGE) not in captured.err, captured.err
    return lines


def a_file(tmp_path: Path) -> Path:
    """A regular file: no folder can be made under it, whoever runs the tests (root too)."""
    blocker = tmp_path / "notes.txt"
    blocker.write_text("a file, not a folder", encoding="utf-8")
    return blocker


# -- outputs that cannot be written -----------------------------------------------------------
@pytest.mark.parametrize("name", ["run.npz", "run.gif", "deeper/run.npz"])
def test_run_refuses_a_recording_it_could_not_write_before_running(tmp_path, capsys, name):
    target = a_file(tmp_path) / name
    assert main(["run", "line-follow", "--duration", "1", "--record", str(target)]) == 2
    lines = error_lines(capsys, "run")
    assert len(lines) == 1
    assert "--record" in lines[0] and "notes.txt" in lines[0] and "is a file" in lines[0]


def test_run_refuses_a_plots_folder_it_could_not_write_before_running(tmp_path, capsys):
    target = a_file(tmp_path) / "plots"
    assert main(["run", "line-follow", "--duration", "1", "--plots", str(target)]) == 2
    (line,) = error_lines(capsys, "run")
    assert "--plots" in line and "choose a folder you can write to" in line


def test_tree_refuses_an_output_it_could_not_write(tmp_path, capsys):
    target = a_file(tmp_path) / "tree.txt"
    assert main(["tree", "-o", str(target)]) == 2
    (line,) = error_lines(capsys, "tree")
    assert "-o" in line and "is a file" in line


@pytest.mark.skipif(
    sys.platform == "win32" or (hasattr(os, "geteuid") and os.geteuid() == 0),
    reason="permission bits do not bind root (and Windows uses access lists), so a "
    "read-only folder cannot be made here; the file-in-the-way tests cover the check",
)
def test_run_refuses_a_read_only_folder(tmp_path, capsys):
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        assert main(["run", "line-follow", "--record", str(folder / "run.npz")]) == 2
    finally:
        folder.chmod(0o755)
    (line,) = error_lines(capsys, "run")
    assert "cannot write in" in line


def test_a_writable_place_is_left_as_it_was(tmp_path, capsys):
    target = tmp_path / "new" / "tree.txt"
    assert main(["tree", "-o", str(target)]) == 0
    assert sorted(p.name for p in target.parent.iterdir()) == ["tree.txt"]  # no probe left


# -- a student's broken code ------------------------------------------------------------------
BROKEN = "from puckboard.behaviours import improved\n\ndef make(:\n    return improved()\n"


def python_shows(path: Path) -> list[str]:
    """What Python itself prints for the syntax error in ``path``, without a traceback."""
    try:
        compile(path.read_text(encoding="utf-8"), str(path), "exec")
    except SyntaxError as exc:
        import traceback

        return "".join(traceback.format_exception_only(type(exc), exc)).splitlines()
    raise AssertionError(f"{path} compiles")


@pytest.mark.parametrize("command", [["run", "--duration", "1"], ["tree"]])
def test_a_syntax_error_in_a_controller_file_is_shown_as_python_shows_it(tmp_path, capsys, command):
    path = tmp_path / "my_layer.py"
    path.write_text(BROKEN, encoding="utf-8")
    assert main([*command, "--controller", f"{path}:make"]) == 2
    lines = error_lines(capsys, command[0])
    assert lines[:-1] == python_shows(path)  # file, line, caret, message: nothing of ours
    assert "syntax error in my_layer.py" in lines[-1]


def test_an_error_at_import_of_a_controller_file_shows_only_the_students_frames(tmp_path, capsys):
    path = tmp_path / "my_layer.py"
    path.write_text("import math\n\nSPEED = math.tau / zero\n", encoding="utf-8")
    assert main(["run", "--duration", "1", "--controller", f"{path}:make"]) == 1
    lines = error_lines(capsys, "run")
    assert lines[0] == "Traceback (most recent call last):"
    assert lines[1] == f'  File "{path}", line 3, in <module>'
    assert lines[-2] == "NameError: name 'zero' is not defined"
    assert not any("importlib" in line or "presets.py" in line for line in lines)
    assert "raised NameError" in lines[-1]


def test_the_loaders_own_messages_stay_one_line(tmp_path, capsys):
    assert main(["tree", "--controller", f"{tmp_path / 'absent.py'}:make"]) == 2
    (line,) = error_lines(capsys, "tree")
    assert "does not exist" in line


def test_a_syntax_error_in_an_example_is_shown_as_python_shows_it(tmp_path, capsys, monkeypatch):
    # an example edited in place: an editable install runs the repository's file
    path = tmp_path / "edited.py"
    path.write_text(BROKEN, encoding="utf-8")
    search = [*puckboard.examples.__path__, str(tmp_path)]
    monkeypatch.setattr(puckboard.examples, "__path__", search)
    monkeypatch.setattr(examples_cli, "example_names", lambda: ["edited"])
    monkeypatch.delitem(sys.modules, "puckboard.examples.edited", raising=False)
    assert main(["examples", "run", "edited"]) == 2
    lines = error_lines(capsys, "examples")
    assert lines[:-1] == python_shows(path)


# -- a connection lost mid-run ----------------------------------------------------------------
def test_warnings_held_back_for_a_lost_connection_come_out_when_the_run_ends_otherwise(caplog):
    from types import SimpleNamespace

    from puckboard.cli.errors import connection_loss_in_one_line
    from puckboard.errors import ConnectionLostError

    log = logging.getLogger("puckboard.control.loop")
    lost = ConnectionLostError("the robot at tcp://127.0.0.1:1 closed the connection")
    held_while_running = []

    def run() -> None:
        with connection_loss_in_one_line(SimpleNamespace()):
            log.warning("could not stop robot %r: %s", "epuck", lost)
            held_while_running.append("could not stop" not in caplog.text)
            raise KeyboardInterrupt  # the run ends, but not on the lost connection

    with caplog.at_level(logging.WARNING), pytest.raises(KeyboardInterrupt):
        run()
    assert held_while_running == [True]
    assert caplog.text.count("could not stop robot 'epuck'") == 1


def test_a_lost_connection_after_which_the_wheels_were_stopped_says_so():
    from types import SimpleNamespace

    from puckboard.cli.errors import connection_lost_error
    from puckboard.errors import ConnectionLostError

    stopped = SimpleNamespace(wheels_stopped=True)
    episode = SimpleNamespace(
        backend="coppeliasim",
        loop=SimpleNamespace(synchronous=True, time=12.345),
        connection=SimpleNamespace(adapters={"left": stopped, "right": stopped}),
    )
    error = connection_lost_error(episode, ConnectionLostError("no answer\nsecond line"))
    assert error.status == 1
    assert str(error) == (
        "the coppeliasim connection was lost at t = 12.35 s of simulated time and the "
        "wheels were stopped. no answer"
    )
