"""Bad input and missing extras end in one line on stderr and exit status 2 (issue 17).

Each test runs ``main([...])`` in-process and checks the whole of stderr: exactly one
line, starting ``puckboard <command>: error:``, that says what was wrong and what to do.
"""

from __future__ import annotations

import errno
import socket
import sys
from pathlib import Path

import pytest

from puckboard.cli import main
from puckboard.cli.bind import bind_error_message
from puckboard.cli.checks import seed_type

SCENE_ROBOT = """
name = "probe"
dt = 0.05
duration = 1.0

[[robots]]
name = "a"
x = 0.0
y = 0.0
theta = 0.0
"""


def one_error_line(capsys: pytest.CaptureFixture[str], command: str) -> str:
    """The single stderr line of a refused command (asserting there is just one)."""
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"puckboard {command}: error: "), err
    return lines[0]


def hide_module(monkeypatch: pytest.MonkeyPatch, name: str, *dependents: str) -> None:
    """Make ``import name`` fail as if it were not installed (``None`` in sys.modules),
    and forget ``dependents`` so that they import it again."""
    for module in list(sys.modules):
        if module.startswith(name + "."):
            monkeypatch.delitem(sys.modules, module)
    monkeypatch.setitem(sys.modules, name, None)
    for module in dependents:
        monkeypatch.delitem(sys.modules, module, raising=False)


# -- 1. missing optional extras ---------------------------------------------------------------
def test_serve_without_pyzmq_names_the_coppeliasim_extra(monkeypatch, capsys):
    hide_module(monkeypatch, "zmq", "puckboard.backends.coppeliasim.server.socket_loop")
    assert main(["serve", "--port", "0"]) == 2
    line = one_error_line(capsys, "serve")
    assert "zmq" in line and "pip install 'puckboard[coppeliasim]'" in line


def test_monitor_without_rich_names_the_cli_extra(monkeypatch, capsys):
    hide_module(monkeypatch, "rich")
    assert main(["monitor", "--duration", "0.1"]) == 2
    line = one_error_line(capsys, "monitor")
    assert "rich" in line and "pip install 'puckboard[cli]'" in line


def test_run_monitor_without_rich_names_the_cli_extra(monkeypatch, capsys):
    hide_module(monkeypatch, "rich")
    assert main(["run", "--monitor", "--duration", "0.1"]) == 2
    line = one_error_line(capsys, "run")
    assert "--monitor" in line and "pip install 'puckboard[cli]'" in line


def test_bench_coppeliasim_suite_without_pyzmq_measures_nothing_and_names_the_extra(
    monkeypatch, capsys
):
    hide_module(monkeypatch, "zmq", "puckboard.backends.coppeliasim.server.socket_loop")
    assert main(["bench", "--suite", "coppeliasim", "--steps", "1", "--json"]) == 2
    line = one_error_line(capsys, "bench")  # every suite asked for was skipped
    assert "nothing was measured: suite 'coppeliasim'" in line
    assert "zmq" in line and "pip install 'puckboard[coppeliasim]'" in line


def test_every_extra_named_in_messages_exists_in_pyproject():
    from puckboard._extras import EXTRA_OF_MODULE

    pyproject = Path(__file__).resolve().parents[2] / "pyproject.toml"
    if not pyproject.is_file():
        pytest.skip("not a source checkout")
    tomllib = pytest.importorskip("tomllib" if sys.version_info >= (3, 11) else "tomli")
    extras = tomllib.loads(pyproject.read_text(encoding="utf-8"))["project"][
        "optional-dependencies"
    ]
    assert set(EXTRA_OF_MODULE.values()) <= set(extras)


# -- 2. durations and ports out of range ------------------------------------------------------
@pytest.mark.parametrize("value", ["inf", "nan", "0", "-1"])
def test_run_duration_must_be_finite_and_positive(capsys, value):
    assert main(["run", "--duration", value]) == 2
    line = one_error_line(capsys, "run")
    assert "--duration must be a finite positive number of seconds" in line


def test_emulate_port_out_of_range(capsys):
    assert main(["emulate", "--port", "99999"]) == 2
    assert "--port must be 0..65535, got 99999" in one_error_line(capsys, "emulate")


# -- 3. too many steps ------------------------------------------------------------------------
def test_run_refuses_an_episode_of_a_billion_steps(capsys):
    assert main(["run", "--set", "dt=1e-9", "--duration", "1"]) == 2
    line = one_error_line(capsys, "run")
    assert "MAX_STEPS" in line and "dt=1e-09" in line and "larger dt" in line


# -- 4. seeds ---------------------------------------------------------------------------------
@pytest.mark.parametrize("command", ["run", "serve", "emulate", "monitor"])
def test_negative_seed_is_named(capsys, command):
    assert main([command, "--seed", "-1"]) == 2
    line = one_error_line(capsys, command)
    assert "--seed must be a whole number ≥ 0, got -1" in line


def test_seed_type_accepts_whole_numbers_only():
    assert seed_type("0") == 0
    assert seed_type("12345678901234567890") == 12345678901234567890
    for bad in ("-1", "1.5", "x", ""):
        with pytest.raises(Exception, match="--seed must be a whole number"):
            seed_type(bad)


# -- 5. why a server cannot listen ------------------------------------------------------------
def test_bind_error_port_in_use():
    msg = bind_error_message(OSError(errno.EADDRINUSE, "Address in use"), "127.0.0.1", 23000)
    assert "in use" in msg and "--port" in msg


def test_bind_error_privileged_port_is_not_blamed_on_another_server():
    msg = bind_error_message(OSError(errno.EACCES, "Permission denied"), "127.0.0.1", 1)
    assert "administrator rights" in msg and "in use" not in msg and "another" not in msg


def test_bind_error_denied_above_1024_says_permission():
    msg = bind_error_message(OSError(errno.EACCES, "Permission denied"), "127.0.0.1", 5000)
    assert "permission denied" in msg and "in use" not in msg


@pytest.mark.parametrize(
    "exc",
    [
        socket.gaierror(socket.EAI_NONAME, "Name or service not known"),
        OSError(socket.EAI_NONAME, "Name or service not known (while attempting to bind)"),
        OSError(errno.EADDRNOTAVAIL, "Cannot assign requested address"),
    ],
)
def test_bind_error_bad_host(exc):
    msg = bind_error_message(exc, "999.1.1.1", 23000)
    assert "'999.1.1.1' is not an address of this machine" in msg and "in use" not in msg


def test_bind_error_finds_the_cause_behind_a_server_s_own_error():
    try:
        try:
            raise OSError(errno.EADDRINUSE, "Address already in use")
        except OSError as inner:
            raise OSError("cannot listen on 127.0.0.1:10000") from inner
    except OSError as outer:
        msg = bind_error_message(outer, "127.0.0.1", 10000)
    assert "in use" in msg


@pytest.mark.parametrize("command", ["serve", "emulate"])
def test_bad_host_is_named_not_blamed_on_another_server(capsys, command):
    assert main([command, "--host", "999.1.1.1", "--port", "0"]) == 2
    line = one_error_line(capsys, command)
    assert "'999.1.1.1' is not an address of this machine" in line
    assert "another server" not in line


# -- 6. puckboard plot ------------------------------------------------------------------------
def test_plot_of_a_file_that_is_not_a_recording(tmp_path, capsys):
    path = tmp_path / "notes.txt"
    path.write_text("not numpy at all\n", encoding="utf-8")
    assert main(["plot", str(path), "--out", str(tmp_path / "plots")]) == 2
    line = one_error_line(capsys, "plot")
    assert "is not a puckboard recording" in line and "pickle" not in line


def test_plot_with_a_reversed_window_writes_nothing(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    run = tmp_path / "run.npz"
    assert main(["run", "--duration", "0.5", "--record", str(run)]) == 0
    capsys.readouterr()
    out = tmp_path / "plots"
    assert main(["plot", str(run), "--from", "50", "--to", "10", "--out", str(out)]) == 2
    assert "--to (10 s) is before --from (50 s)" in one_error_line(capsys, "plot")
    animation = tmp_path / "run.gif"
    args = ["plot", str(run), "--from", "50", "--to", "60", "--animate", str(animation)]
    assert main([*args, "--out", str(out)]) == 2
    assert "nothing to animate" in one_error_line(capsys, "plot")
    assert not out.exists() and not animation.exists()


# -- 8. scene files ---------------------------------------------------------------------------
def test_scene_with_a_text_position_names_the_field_and_asks_for_a_number(tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE_ROBOT + '\n[[obstacles]]\nx = "xx"\nradius = 0.02\n', encoding="utf-8")
    assert main(["run", str(scene)]) == 2
    line = one_error_line(capsys, "run")
    assert "obstacles[0].x: expected a number (m), got 'xx'" in line


def test_scene_with_a_missing_position_says_an_obstacle(tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE_ROBOT + "\n[[obstacles]]\ny = 0.2\nradius = 0.02\n", encoding="utf-8")
    assert main(["run", str(scene)]) == 2
    line = one_error_line(capsys, "run")
    assert "obstacles[0].x: missing; an obstacle needs numbers x and y" in line


def test_a_layer_that_raises_ends_with_a_line_saying_robot_time_and_layer(tmp_path, capsys):
    """The traceback says what went wrong; the last line says where, in the run's terms."""
    module = tmp_path / "broken.py"
    module.write_text(
        "from puckboard.behaviours import Controller, Cruise, Layer\n"
        "class Fragile(Layer):\n"
        "    reads = ('ground',)\n"
        "    def applies(self, frame):\n"
        "        if frame.time > 2.0:\n"
        "            raise ZeroDivisionError('the student divided by zero')\n"
        "        return False\n"
        "    def command(self, frame):\n"
        "        return None\n"
        "def make():\n"
        "    return Controller([Fragile(), Cruise()])\n",
        encoding="utf-8",
    )
    status = main(["run", "line-follow", "--controller", f"{module}:make", "--duration", "5"])
    assert status == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert any("ZeroDivisionError" in line for line in err[:-1])  # the traceback is kept
    assert err[-1].startswith("puckboard run: error: robot 'epuck' at t = 2.")
    assert "in layer 'Fragile': ZeroDivisionError: the student divided by zero" in err[-1]
