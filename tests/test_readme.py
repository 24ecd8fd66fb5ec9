"""The README's promises: two set-up commands first, a layer example whose effect shows,
and every output it shows exactly what the commands print (numbers included; only
wall-clock figures masked, and ``...`` lines elided)."""

from __future__ import annotations

import doctest
import re
import shlex
from pathlib import Path

import doc_pages
import pytest

from puckboard.control.episode import Episode

README = Path(__file__).resolve().parent.parent / "README.md"


def readme() -> str:
    return README.read_text(encoding="utf-8")


def layer_example() -> str:
    """The README's one Python block: the layer example, saved as ``mylayers.py``."""
    blocks = [body for language, body in doc_pages.fences(readme()) if language == "python"]
    assert len(blocks) == 1, "the README should have exactly one python block, the example"
    return blocks[0]


@pytest.fixture
def in_student_folder(tmp_path, monkeypatch):
    """A folder holding the README's ``mylayers.py``, as the reader is told to save it."""
    (tmp_path / "mylayers.py").write_text(layer_example(), encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    return tmp_path


def test_readme_opens_with_the_two_setup_commands():
    text = readme()
    first_block = re.search(r"```bash\n(.*?)```", text, re.S)
    assert first_block is not None
    assert text.index("```bash") < text.index("\n## ")  # before any section
    commands = [line for line in first_block.group(1).splitlines() if line.strip()]
    assert len(commands) == 2
    assert commands[0].endswith("puckboard run")
    assert "pytest" in commands[1]


def console_sessions() -> list[tuple[str, str]]:
    """Every ``$ puckboard ...`` command of the README's console blocks, with the output
    shown under it."""
    sessions = []
    for language, body in doc_pages.fences(readme()):
        if language != "console":
            continue
        for chunk in re.split(r"^(?=\$ )", body, flags=re.MULTILINE):
            if chunk.startswith("$ "):
                command, _, shown = chunk.partition("\n")
                sessions.append((command[2:].strip(), shown))
    return sessions


def test_the_readme_shows_its_commands_outputs():
    commands = [command for command, _ in console_sessions()]
    assert commands[0] == "puckboard run", commands  # the flagship, first
    assert "puckboard run --controller mylayers.py:make --seed 8" in commands


@pytest.mark.slow
@pytest.mark.parametrize(
    ("command", "shown"), console_sessions(), ids=[c for c, _ in console_sessions()]
)
def test_every_output_the_readme_shows_is_what_the_command_prints(
    command, shown, in_student_folder, capsys
):
    from puckboard.cli import main

    argv = shlex.split(command)
    assert argv[0] == "puckboard", command
    assert main(argv[1:]) == 0, command
    doc_pages.assert_shown(shown, capsys.readouterr().out, f"README: $ {command}")


@pytest.mark.slow
def test_the_readme_python_session_prints_what_it_shows(in_student_folder):
    """The ``pycon`` block runs as a doctest, in the folder that holds ``mylayers.py``."""
    (session,) = [body for language, body in doc_pages.fences(readme()) if language == "pycon"]
    test = doctest.DocTestParser().get_doctest(session, {}, "README", "README.md", 0)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    runner.run(test)
    assert runner.failures == 0 and runner.tries >= 3, runner.summarize()


@pytest.mark.slow
def test_the_readme_example_layer_takes_control(in_student_folder):
    """The example's own layer drives at some point (an example layer that never applies
    would print exactly what ``improved`` prints, and teach nothing): on seed 8 it brings
    the robot that dodged to the outside, ``right``, back to the line."""
    episode = Episode("two-robot-pass", controller="mylayers.py:make", seed=8)
    drivers: dict[str, set[str]] = {"left": set(), "right": set()}

    def note(ep):
        for name, seen in drivers.items():
            seen.add(ep.blackboard.value(f"{name}/command/layer"))

    episode.add_observer(note)
    result = episode.run()
    assert result.success, result.failures
    assert "FindLineOnTheRight" in drivers["right"], drivers


def test_the_readme_names_no_test_count():
    """A count of tests drifts with every test added; the README gives the command."""
    assert not re.search(r"\b\d[\d,]* tests\b", readme()), "the README states a test count"


def test_the_readme_names_every_extra():
    """Each optional part of pyproject.toml is named, so a reader learns it exists."""
    import tomllib

    pyproject = README.parent / "pyproject.toml"
    extras = tomllib.loads(pyproject.read_text(encoding="utf-8"))["project"][
        "optional-dependencies"
    ]
    missing = [name for name in extras if f'".[{name}]"' not in readme()]
    assert not missing, f"extras the README does not name: {missing}"


def test_the_readme_says_what_the_stock_run_warns(caplog):
    """The stock transcript shows stdout; the warning the command prints on stderr is
    quoted word for word in the note under it."""
    import logging

    from puckboard.cli import main

    (quoted,) = re.findall(r"`WARNING (.+?)`", readme(), re.S)
    with caplog.at_level(logging.WARNING):
        assert main(["run", "--controller", "stock"]) == 0
    logged = [f"{r.name}: {r.getMessage()}" for r in caplog.records if r.levelno == logging.WARNING]
    assert " ".join(quoted.split()) in logged


def test_the_readme_gives_the_picture_before_the_commands_and_the_test_time():
    """A newcomer reads what puckboard is for before a command, and how long the test
    command takes before running it."""
    text = readme()
    opening = text[: text.index("```bash")]
    assert "e-puck" in opening and "layers" in opening and "%" not in opening
    said = re.findall(r"about (\d+) minutes on 2 cores", text)
    assert len(said) == 2 and len(set(said)) == 1  # both places give the same figure
