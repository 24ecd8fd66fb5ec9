"""Messages a newcomer reads: grammar that fits the case, nothing ignored or done unsaid."""

from __future__ import annotations

import pytest

from puckboard.cli import main
from puckboard.cli.examples import takes_arguments


def error_line(capsys: pytest.CaptureFixture[str], command: str) -> str:
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"puckboard {command}: error: "), err
    return lines[0]


@pytest.mark.parametrize(
    ("flags", "expected"),
    [
        (["--host", "h"], "--host does not apply to the embedded backend; use it with"),
        (["--host", "h", "--port", "1"], "--host and --port do not apply to the embedded backend;"
         " use them with"),
        (["--host", "h", "--port", "1", "--device", "d"], "--host, --port and --device do not"),
    ],
)  # fmt: skip
def test_backend_options_for_the_embedded_backend_are_refused_in_good_grammar(
    capsys, flags, expected
):
    assert main(["run", *flags]) == 2
    line = error_line(capsys, "run")
    assert expected in line and "--backend coppeliasim, epuck2-wifi or sercom" in line


def test_a_window_past_the_run_is_described_as_it_was_given():
    pytest.importorskip("matplotlib")
    from puckboard.control.episode import Episode
    from puckboard.recording.recorder import Recorder
    from puckboard.viz.animation import frame_indices

    episode = Episode("line-follow", seed=0)
    recorder = Recorder.for_episode(episode, None)
    episode.add_observer(recorder)
    episode.run(1.0)
    rec = recorder.close()
    with pytest.raises(ValueError, match=r"^nothing to animate from 100 s on: the run covers"):
        frame_indices(rec, 10.0, 4.0, start=100.0)
    with pytest.raises(ValueError, match=r"^nothing to animate between 5 s and 7.5 s: the run"):
        frame_indices(rec, 10.0, 4.0, start=5.0, end=7.5)


def test_passed_other_is_no_question_for_a_robot_alone(capsys):
    assert main(["run", "line-follow", "--duration", "1"]) == 0
    row = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("epuck"))
    assert row.split()[-1] == "-"


def test_passed_other_is_answered_when_there_is_another_robot(capsys):
    assert main(["run", "two-robot-pass", "--duration", "1"]) == 0
    out = capsys.readouterr().out.splitlines()
    rows = [line for line in out if line.startswith(("left ", "right "))]
    assert len(rows) == 2 and all(row.split()[-1] == "no" for row in rows)


def test_examples_refuse_arguments_they_would_ignore(capsys):
    assert not takes_arguments("first_layer") and takes_arguments("go_home")
    assert main(["examples", "run", "first_layer", "--bogus"]) == 2
    line = error_line(capsys, "examples")
    assert "'first_layer' takes no arguments, got '--bogus'" in line and "go_home" in line
    assert main(["examples", "show", "first_layer", "extra"]) == 2
    assert "takes only a NAME, got 'extra'" in error_line(capsys, "examples")


def test_a_duration_shorter_than_one_step_is_refused_not_rounded_up_unsaid(capsys):
    assert main(["run", "line-follow", "--duration", "0.0001"]) == 2
    line = error_line(capsys, "run")
    assert "0.0001 s is shorter than one simulation step of 0.05 s" in line
    assert "give at least 0.05 s" in line


def test_one_step_is_one_step(capsys):
    assert main(["run", "line-follow", "--duration", "0.05"]) == 0
    assert "1 step of 50 ms)" in capsys.readouterr().out


def test_event_lines_set_the_robots_name_off_from_the_events_words(capsys):
    """Robots called left and right: '5.00 s  left: left the line', as the web view and
    the animation say it, never 'left  left_line'."""
    from puckboard.control.episode import run_episode
    from puckboard.viz.style import event_label

    assert main(["run", "--duration", "12"]) == 0
    out = capsys.readouterr().out
    shown = out[out.index("\nevents:\n") + len("\nevents:\n") :].splitlines()
    result = run_episode("two-robot-pass", seed=0, duration=12.0)
    events = sorted(result.events, key=lambda e: e.time_s)
    assert any(e.robot == "left" and e.kind == "left_line" for e in events)
    assert shown == [
        f"  {e.time_s:7.2f} s  " + (f"{e.robot}: " if e.robot else "") + event_label(e.kind)
        for e in events
    ]
