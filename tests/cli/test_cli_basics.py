"""The ``puckboard`` command's own options."""

from __future__ import annotations

import subprocess
import sys

import pytest

import puckboard
from puckboard.cli import main


def test_version(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert puckboard.__version__ in capsys.readouterr().out


def test_help_lists_subcommands(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    out = capsys.readouterr().out
    assert "usage: puckboard" in out


def test_unknown_subcommand_is_an_error(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["frobnicate"])
    assert exc.value.code == 2
    assert "invalid choice" in capsys.readouterr().err


def test_python_dash_m_works():
    out = subprocess.run(
        [sys.executable, "-m", "puckboard", "--version"], capture_output=True, text=True
    )
    assert out.returncode == 0
    assert puckboard.__version__ in out.stdout


def test_scenes_lists_each_scene_with_its_description(capsys):
    """What ``arena``'s description claims of the controllers is measured in
    tests/test_doc_claims.py; here, that the listing shows it."""
    from puckboard.cli import main
    from puckboard.scenario.scenefile import scene_description

    assert main(["scenes"]) == 0
    arena = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("arena"))
    assert scene_description("arena") in " ".join(arena.split())


def test_scenes_show_prints_a_scene_file_it_was_given(tmp_path, capsys):
    """The refusal of an unknown name suggests giving a scene file: 'show' takes one."""
    from puckboard.cli import main

    assert main(["scenes", "show", "two-robot-pass"]) == 0
    shipped = capsys.readouterr().out
    mine = tmp_path / "my_scene.toml"
    mine.write_text(shipped.replace("two-robot-pass", "mine"), encoding="utf-8")
    assert main(["scenes", "show", str(mine)]) == 0
    assert capsys.readouterr().out == mine.read_text(encoding="utf-8")
    broken = tmp_path / "broken.toml"
    broken.write_text("robots = 3\n", encoding="utf-8")
    assert main(["scenes", "show", str(broken)]) == 2  # checked as 'run' would check it
    assert "broken.toml" in capsys.readouterr().err


@pytest.mark.parametrize("command", ["serve", "emulate", "calibrate"])
def test_help_has_no_rest_markup_and_every_option_is_explained(command, capsys):
    import argparse

    from puckboard.cli import build_parser, main

    with pytest.raises(SystemExit):
        main([command, "--help"])
    assert "``" not in capsys.readouterr().out
    subparsers = next(
        a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction)
    )
    parser = subparsers.choices[command]
    unexplained = [a.option_strings[0] for a in parser._actions if a.option_strings and not a.help]
    assert unexplained == []


def test_a_reader_that_goes_away_ends_the_command_quietly(monkeypatch):
    """'puckboard profiles | head -2' must not end in a BrokenPipeError traceback."""
    import sys

    from puckboard.cli import main

    class ClosedPipe:
        def write(self, text):
            raise BrokenPipeError(32, "Broken pipe")

        def flush(self):
            pass

    monkeypatch.setattr(sys, "stdout", ClosedPipe())
    assert main(["profiles"]) == 0
